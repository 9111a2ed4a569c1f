"""Render the generated plant module of a :class:`~clutchsim.network.plant.Plan`.

See :mod:`clutchsim.network.codegen` for the mechanics.  Every function of the module
starts from the same *body* (node speeds, the components' equations, node torques,
generalised forces, the switching block, accelerations); ``rhs`` stops there, ``jac`` adds
the partial derivatives, ``events``/``outputs``/``reset`` the *full* extras (stick torques of
sliding switching elements, node accelerations, torques in rigid parts).
"""

from __future__ import annotations

import re

import numpy as np

from ..core.status import Action
from ..friction._common import FREE_SCALE
from ..friction.base import RESET_CHANGED, RESET_NONE, RESET_RELEASED, RESET_STUCK
from .codegen import ENERGY
from .elimination import elimination_source

_ACTIONS = {"continue": int(Action.CONTINUE), "stop": int(Action.STOP),
            "fail": int(Action.FAIL)}
_CHANGED = int(Action.STATE_CHANGED)
_CONT = int(Action.CONTINUE)
_PASS = int(Action.PASS)
NO_EVENT = 1.0
#: slots of ``aux`` per friction element: slip, scale, stick torque, torque, shielded, and
#: the flange-a torque of a lossy gear
AUX_W = 6


def _lockable(c) -> bool:
    """Does the plant lock and free element ``c`` (an element with a lockable model, a
    one-way clutch, a lossy gear: the element's ``lockable``)?"""
    return bool(getattr(c, "lockable", False))


def _stick_slip(c) -> bool:
    """Is ``c`` an element whose model is a stick/slip state machine the plant locks and
    frees (:attr:`~clutchsim.friction.FrictionModel.lockable`): in its stuck mode it may
    also sit unlocked, holding what it can of a part that other elements hold?"""
    return _lockable(c) and not _lossy(c) and c.model.lockable


def _lossy(c) -> bool:
    """Is ``c`` the loss element of a lossy gear (its torque solved from the torque it
    transmits, not by a friction model)?"""
    return bool(getattr(c, "lossy", False))


def _ind(lines, k=1):
    pad = "    " * k
    out = []
    for ln in lines:
        for sub in ln.split("\n"):
            out.append(pad + sub if sub else "")
    return out


class _PlantRenderer:
    """Writes the generated plant module of ``plan`` from the components' generated
    equations ``g``; the helpers below name the entries of the parameter vector ``p``
    (the derived block of :class:`~clutchsim.network.plant.Plan`) that the code reads."""

    def __init__(self, plan, g):
        self.P = plan
        self.g = g
        self.asm = plan.asm
        self.n = plan.n
        self.nv = plan.asm.n_v
        self.m = len(plan.sw)
        self.fe = plan.fes
        self.mpat = plan.minv_pattern()
        self.imports: set = set()
        # scheduled value changes (gear shifts): one bank of values per event, in order
        self.banks = [ev for ev in g.events if ev[3] == "bank"]
        counts: dict = {}
        plan.banks = []
        for ev in self.banks:
            plan.banks.append((ev[4], counts.get(ev[4], 0)))
            counts[ev[4]] = counts.get(ev[4], 0) + 1
        # banks without a time (triggered changes, Component.schedule): the component whose
        # values each one switches, else None
        comps = {c.name: c for c in plan.net.components}
        self.triggered = [name if comps[name].schedule()[j][0] is None else None
                          for name, j in plan.banks]

    # ------------------------------------------------------------ helpers
    def inv_mass(self, i, j):
        """``M⁻¹[i, j]``: the inverse mass matrix of the independent speeds."""
        return f"p[{self.P.off_Minv + i * self.nv + j}]"

    def minv_row(self, k, vec):
        """``Σ_j M⁻¹[k, j]·vec_j`` over the structurally non-zero entries."""
        return " + ".join(f"{self.inv_mass(k, j)} * {vec(j)}" for j in range(self.nv)
                          if self.mpat[k, j]) or "0.0"

    def slip_row(self, j, k):
        """``B[j, k]``: the slip of switching element ``j`` per independent speed ``k``."""
        return f"p[{self.P.off_B + j * self.nv + k}]"

    def inv_mass_slip(self, k, j):
        """``(M⁻¹·Bᵀ)[k, j]``: speed ``k``'s response to a unit torque of element ``j``."""
        return f"p[{self.P.off_MB + k * self.m + j}]"

    def node_inertia(self, n):
        """``J[n]``: the inertia at node ``n``."""
        return f"p[{self.P.off_J + n}]"

    def expand(self, target, row, key, expr):
        """``target[row, col] += d/dcol`` for a partial ``expr`` with respect to ``key``."""
        kind, idx = key
        if kind == "y":
            return [f"{target}[{row}, {idx}] += {expr}"]
        n = idx
        if n == self.asm.ground:
            return []
        if n in self.asm.free:
            return [f"{target}[{row}, {self.asm.free.index(n)}] += {expr}"]
        out = []
        for k in range(self.nv):
            if self.asm.pattern[n][k]:
                out.append(f"{target}[{row}, {k}] += ({expr}) * {self.P.N(n, k)}")
        return out

    def fe_meta(self, c):
        e = self.P.fe_index[c.name]
        o, npar = self.P.tables[(c.name, "model")]
        nz = c.model.n_states
        iz = self.P.state_index[(c.name, "z0")] if nz else 0
        return e, o, npar, nz, iz

    def kernel(self, c, kind):
        """Name of the ``kind`` kernel the element's model declares (its ``kernels``, e.g.
        ``mykhailevych2020_force``), imported from where it is defined: called directly,
        not through the dispatcher over all models, so that a plant compiles only the
        kernels it uses."""
        fn = c.model.kernels.get(kind)
        self.imports.add((fn.__module__, fn.__name__))
        return fn.__name__

    def fcall(self, fn, c, fe_arg, dz=None, extra=""):
        e, o, npar, nz, iz = self.fe_meta(c)
        dz = dz or f"dy[{iz}:{iz + nz}]"
        kind = {"friction_force": "force", "friction_jacobian": "jacobian"}[fn]
        return (f"{self.kernel(c, kind)}(p[{o}:{o + npar}], y[{iz}:{iz + nz}], s{e}, "
                f"{fe_arg}, sc{e}, {dz}{extra})")

    def force(self, c, fe_arg):
        """Expression: the friction force of element ``c`` (its kernel with the stick force
        ``fe_arg``), plus the drag of an open element that declares one."""
        return f"{self.fcall('friction_force', c, fe_arg)}{self.drag(c)}"

    def drag(self, c):
        e = self.P.fe_index[c.name]
        if getattr(c, "has_drag", False):
            return f" + p[{self.P.slot[(c.name, 'drag')]}] * math.tanh(s{e})"
        return ""

    def lock_test(self, c):
        """Expression: is element ``c`` locked now?  (``False`` for one the plant never
        locks.)"""
        if _lockable(c):
            return f"y[{self.P.state_index[(c.name, 'locked')]}] > 0.5"
        return "False"

    def lossy_meta(self, c):
        """(sw index, relation row, flange-a node, table offset, rows) of a lossy gear."""
        i = self.P.sw_index[c.name]
        r = self.P.relation_row[(c.name, 0)]
        na = self.asm.node_of[(c.name, "a")]
        o, npar = self.P.tables[(c.name, "model")]
        return i, r, na, o, npar // 5

    def relation_pinv(self, r, n):
        """Entry ``(r, n)`` of the pseudo-inverse that gives the multiplier (the torque) of
        rigid relation ``r`` from the node torque residuals."""
        return f"p[{self.P.off_Gp + r * self.asm.n_nodes + n}]"

    def relation(self, r, n):
        """``G[r, n]``: the coefficient of node ``n``'s speed in rigid relation ``r``."""
        return f"p[{self.P.off_G + r * self.asm.n_nodes + n}]"

    # ------------------------------------------------------------ body
    def body(self, full: bool) -> list[str]:
        P, asm, g = self.P, self.asm, self.g
        L = []
        for n in range(asm.n_nodes):
            L.append(f"w{n} = {P.node_speed(n)}")
        for c in P.sw:
            if _lockable(c):                 # the lock flag is constant between events
                L.append(f"dy[{P.state_index[(c.name, 'locked')]}] = 0.0")
            if _lossy(c):                    # so is a lossy gear's rolling direction
                L.append(f"dy[{P.state_index[(c.name, 'z0')]}] = 0.0")
        L += g.body
        # smooth friction elements (no stick torque)
        for c in self.fe:
            e = P.fe_index[c.name]
            if c.name in P.sw_index:
                continue
            L.append(f"fT{e} = {self.force(c, '0.0')}")
            L.append(f"Fe{e} = 0.0")
            L.append(f"sh{e} = 0.0")
        tsum = {}
        for node, expr in g.torques:
            tsum.setdefault(node, []).append(f"({expr})")
        for c in self.fe:
            if c.name in P.sw_index:
                continue
            e = P.fe_index[c.name]
            gv = P.slips[c.name]
            for n in np.flatnonzero(gv):
                tsum.setdefault(int(n), []).append(f"({-float(gv[n])!r} * fT{e})")
        for n in range(asm.n_nodes):
            L.append(f"T{n} = {' + '.join(tsum.get(n, [])) or '0.0'}")
        for k in range(self.nv):
            terms = [f"{P.N(n, k)} * T{n}" for n in range(asm.n_nodes)
                     if asm.pattern[n][k]]
            L.append(f"F{k} = {' + '.join(terms) or '0.0'}")
        if self.m:
            L += self.switch_block(full)
        else:
            for k in range(self.nv):
                L.append(f"a{k} = " + self.minv_row(k, lambda j: f"F{j}"))
        for k in range(self.nv):
            L.append(f"dy[{k}] = a{k}")
        for idx, expr in g.derivs:
            L.append(f"dy[{idx}] = {expr}")
        for n, idx in P.angle_states:        # angle states: the node's speed
            L.append(f"dy[{idx}] = w{n}")
        # heat into thermal nodes
        q = {}
        for node, expr in g.heats:
            q.setdefault(node, []).append(f"({expr})")
        for c in self.fe:
            e = P.fe_index[c.name]
            L.append(f"q{e} = abs(fT{e} * s{e})")
            for node, share in c.heat_shares():
                q.setdefault(node, []).append(f"p[{P.slot[(c.name, share)]}] * q{e}")
        for c in P.thermal:
            idx = P.state_index[(c.name, "theta")]
            cap = f"p[{P.slot[(c.name, 'capacity')]}]"
            L.append(f"dy[{idx}] = ({' + '.join(q.get(c.name, [])) or '0.0'}) / {cap}")
        # energy accounts
        pw = {acc: [] for _, acc in ENERGY}
        for acc, expr in g.powers:
            pw[acc].append(f"({expr})")
        for c in self.fe:
            e = P.fe_index[c.name]
            pw["fric"].append(f"fT{e} * s{e}")
        for i, (_name, acc) in enumerate(ENERGY):
            L.append(f"dy[{P.y_energy + i}] = {' + '.join(pw[acc]) or '0.0'}")
        for c in self.fe:                    # each element's own friction work
            if (c.name, "work") in P.state_index:
                e = P.fe_index[c.name]
                L.append(f"dy[{P.state_index[(c.name, 'work')]}] = fT{e} * s{e}")
        for c in P.wearing:                  # lining wear (network/wear.py)
            L += self.wear_rate(c)
            L.append(f"dy[{P.state_index[(c.name, 'wear')]}] = kw{P.fe_index[c.name]} * "
                     f"q{P.fe_index[c.name]}")
        if full:
            for n in range(asm.n_nodes):
                terms = [f"{P.N(n, k)} * a{k}" for k in range(self.nv) if asm.pattern[n][k]]
                L.append(f"al{n} = {' + '.join(terms) or '0.0'}")
            # torques in rigid parts: G^T lam = J al - T (all applied torques)
            tot = {n: [f"T{n}"] for n in range(asm.n_nodes)}
            for c in P.sw:
                e = P.fe_index[c.name]
                gv = P.slips[c.name]
                for n in np.flatnonzero(gv):
                    tot[int(n)].append(f"({-float(gv[n])!r} * fT{e})")
            for n in range(asm.n_nodes):
                L.append(f"R{n} = {self.node_inertia(n)} * al{n} - ({' + '.join(tot[n])})")
            nn = asm.n_nodes
            for r in range(P.n_rel):
                terms = [f"p[{P.off_Gp + r * nn + n}] * R{n}" for n in range(nn)]
                L.append(f"lam{r} = {' + '.join(terms)}")
        return L

    def work_rows(self, c) -> tuple[int, ...]:
        """The rows a friction element's power ``fT·s`` goes to: ``W_friction`` and, where
        the plant has several friction elements, the element's own ``W_friction_<name>``."""
        own = self.P.state_index.get((c.name, "work"))
        return (self.P.y_energy + 1,) if own is None else (self.P.y_energy + 1, own)

    def wear_rate(self, c) -> list[str]:
        """``kw<e> = k(θ)/area`` and ``dkw<e> = d(kw)/dθ`` (:mod:`clutchsim.network.wear`)."""
        P, e = self.P, self.P.fe_index[c.name]
        sl = {k: f"p[{P.slot[(c.name, k)]}]" for k in
              ("wear_k", "wear_EaR", "wear_Tref", "wear_thc", "wear_gain")}
        th = f"y[{P.state_index[(c.heat[0][0], 'theta')]}]"
        return [f"wT{e} = {th} + 273.15",
                (f"wa{e} = {sl['wear_k']} * math.exp({sl['wear_EaR']} * "
                 f"(1.0 / {sl['wear_Tref']} - 1.0 / wT{e}))"),
                f"wx{e} = {th} - {sl['wear_thc']}",
                f"wc{e} = 1.0 + {sl['wear_gain']} * wx{e} if wx{e} > 0.0 else 1.0",
                f"kw{e} = wa{e} * wc{e}",
                (f"dkw{e} = wa{e} * {sl['wear_EaR']} / (wT{e} * wT{e}) * wc{e} + "
                 f"(wa{e} * {sl['wear_gain']} if wx{e} > 0.0 else 0.0)")]

    def switch_block(self, full: bool) -> list[str]:
        P, m, nv = self.P, self.m, self.nv
        L = [f"act = local_zeros({m})", f"rr = local_empty({m})", f"tau = local_empty({m})",
             f"shl = local_empty({m})"]
        for i, c in enumerate(P.sw):
            e = P.fe_index[c.name]
            L.append(f"locked{e} = {self.lock_test(c)}")
            if _lossy(c):
                L.append(f"F1_{e} = 0.0")
            else:
                L.append(f"F1_{e} = 0.0 if locked{e} else {self.force(c, '0.0')}")
        # generalised forces with the pass-1 forces of the free elements
        for k in range(nv):
            terms = [f"F1_{P.fe_index[c.name]} * {self.slip_row(i, k)}" for i, c in enumerate(P.sw)
                     if not _lossy(c)]
            L.append(f"G{k} = F{k} - ({' + '.join(terms) or '0.0'})")
        for c in P.sw:
            if _lossy(c):
                L += self.lossy_roll(c)
        # stick torques: every free element in the full evaluation; else those whose force
        # reads it (models that are not locked by the plant, and coulomb-robust elements
        # in their stuck mode while unlocked: a holder that takes what it can, up to its
        # capacity, of a part that another element holds)
        need_hyp = [c for c in P.sw if full or not _lockable(c) or _stick_slip(c)]
        if need_hyp:
            for k in range(nv):
                L.append(f"aG{k} = " + self.minv_row(k, lambda j: f"G{j}"))
        for i, c in enumerate(P.sw):
            e = P.fe_index[c.name]
            if c in need_hyp:
                skip = f"locked{e}"
                if not full and _stick_slip(c):
                    skip += f" or y[{P.state_index[(c.name, 'z0')]}] != 0.0"
                lines = [f"if {skip}:", f"    fT{e} = 0.0 if locked{e} else F1_{e}\n    Fe{e} = 0.0",
                         "else:"]
                inner = []
                for j, c2 in enumerate(P.sw):
                    e2 = P.fe_index[c2.name]
                    inner.append(f"act[{j}] = 1.0 if ({j} == {i} or locked{e2}) else 0.0")
                    inner.append(f"rr[{j}] = " + " + ".join(
                        f"{self.slip_row(j, k)} * aG{k}" for k in range(nv))
                        + f" + F1_{e} * p[{P.off_S + j * m + i}]")
                inner.append(f"lock_solve(p, {P.off_S}, {m}, act, rr, tau, shl)")
                inner.append(f"Fe{e} = tau[{i}]")
                if _lossy(c):
                    inner.append(f"fT{e} = F1_{e}")
                else:
                    inner.append(f"fT{e} = {self.force(c, f'Fe{e}')}")
                L += lines + _ind(inner)
            else:
                L.append(f"Fe{e} = 0.0")
                L.append(f"fT{e} = 0.0 if locked{e} else F1_{e}")
        for k in range(nv):
            terms = [f"(0.0 if locked{P.fe_index[c.name]} else fT{P.fe_index[c.name]}) * "
                     f"{self.slip_row(i, k)}" for i, c in enumerate(P.sw)]
            L.append(f"F{k} = F{k} - ({' + '.join(terms)})")
        for k in range(nv):
            L.append(f"a{k} = " + self.minv_row(k, lambda j: f"F{j}"))
        L += self.locked_solve(lambda k: f"a{k}")
        for i, c in enumerate(P.sw):
            e = P.fe_index[c.name]
            L.append(f"sh{e} = shl[{i}]")
            L.append(f"if locked{e}:")
            L.append(f"    fT{e} = tau[{i}]")
            L.append(f"    Fe{e} = tau[{i}]")
            if not _lossy(c):
                L.append(f"    {self.fcall('friction_force', c, f'Fe{e}')}")
        return L

    def locked_solve(self, acc) -> list[str]:
        """Remove from the accelerations ``acc(k)`` what the locked elements hold: their
        torques into ``tau`` (``act`` marks them)."""
        P, m, nv = self.P, self.m, self.nv
        L = []
        for i, c in enumerate(P.sw):
            L.append(f"act[{i}] = 1.0 if locked{P.fe_index[c.name]} else 0.0")
            L.append(f"rr[{i}] = " + " + ".join(f"{self.slip_row(i, k)} * {acc(k)}"
                                                for k in range(nv)))
        L.append(f"lock_solve(p, {P.off_S}, {m}, act, rr, tau, shl)")
        for k in range(nv):
            terms = [f"{self.inv_mass_slip(k, i)} * tau[{i}]" for i in range(m)]
            L.append(f"{acc(k)} = {acc(k)} - ({' + '.join(terms)})")
        return L

    def lossy_roll(self, c) -> list[str]:
        """The loss ``F1_<e>`` of a rolling lossy gear (0 while it sticks).

        Its flange-a torque is ``T_a = L − Q_a`` (``Q_a``: the torque of the gear's rigid
        relation on node a).  Everything is linear in ``L`` for a given set of locked
        elements: ``T_a = T_a0 + kk·L``, with ``T_a0`` from the accelerations without the
        loss (``xa``) and ``kk`` from the response to a unit loss (``xu``, which the
        Jacobian reuses).  :func:`~clutchsim.network._kernels.lossy_solve` closes the loop.
        """
        P, nv = self.P, self.nv
        e = P.fe_index[c.name]
        i, r, na, o, nrow = self.lossy_meta(c)
        iz = P.state_index[(c.name, "z0")]
        gi = P.slips[c.name]
        b = []
        for k in range(nv):
            b.append(f"xa{e}_{k} = " + self.minv_row(k, lambda j: f"G{j}"))
        b += self.locked_solve(lambda k: f"xa{e}_{k}")
        b += self.lam_row(e, r, f"xa{e}_", "tau", free_f1=True)
        b.append(f"Ta0_{e} = -{self.relation(r, na)} * lamx{e}")
        for k in range(nv):
            b.append(f"xu{e}_{k} = -(" + self.minv_row(k, lambda j: self.slip_row(i, j)) + ")")
        b += self.locked_solve(lambda k: f"xu{e}_{k}")
        b += self.lam_row(e, r, f"xu{e}_", "tau", free_f1=False, unit=gi)
        b.append(f"kk{e} = 1.0 - {self.relation(r, na)} * lamx{e}")
        b.append(f"(c1_{e}, c2_{e}, c3_{e}, c4_{e}, c5_{e}, c6_{e}, c7_{e}, c8_{e}, "
                 f"c9_{e}) = lossy_coeffs(p, {o}, {nrow}, s{e})")
        b.append(f"F1_{e}, dLT{e}, dLs{e} = lossy_solve(y[{iz}], Ta0_{e}, kk{e}, c1_{e}, "
                 f"c2_{e}, c3_{e}, c4_{e}, c5_{e}, c6_{e}, c7_{e}, c8_{e}, c9_{e})")
        b.append(f"dLs{e} = dLs{e} * (1.0 if s{e} >= 0.0 else -1.0)")
        for k in range(nv):
            b.append(f"G{k} = G{k} - F1_{e} * {self.slip_row(i, k)}")
        L = [f"F1_{e} = 0.0", f"dLT{e} = 0.0", f"dLs{e} = 0.0"]
        L += [f"xu{e}_{k} = 0.0" for k in range(nv)]
        L += [f"if not locked{e}:"] + _ind(b)
        self.imports.add(("clutchsim.network._kernels", "lossy_coeffs"))
        self.imports.add(("clutchsim.network._kernels", "lossy_solve"))
        return L

    def lam_row(self, e, r, acc, tau, *, free_f1: bool, unit=None) -> list[str]:
        """``lamx<e>``: the multiplier of rigid relation ``r`` for the accelerations
        ``acc<k>`` and lock torques ``tau``, with the applied torques of the body and the
        pass-1 forces (``free_f1``), or with a unit loss of the slip vector ``unit``."""
        P, asm, nv, nn = self.P, self.asm, self.nv, self.asm.n_nodes
        lines = []
        terms = []
        for n in range(nn):
            al = " + ".join(f"{P.N(n, k)} * {acc}{k}" for k in range(nv)
                            if asm.pattern[n][k]) or "0.0"
            applied = []
            if free_f1:
                applied.append(f"T{n}")
            for j, c2 in enumerate(P.sw):
                gv = P.slips[c2.name]
                if gv[n] == 0.0:
                    continue
                e2 = P.fe_index[c2.name]
                f1 = f"F1_{e2}" if free_f1 else "0.0"
                applied.append(f"{-float(gv[n])!r} * ({tau}[{j}] if locked{e2} else {f1})")
            if unit is not None and unit[n] != 0.0:
                applied.append(f"{-float(unit[n])!r}")
            lines.append(f"Rx{e}_{n} = {self.node_inertia(n)} * ({al}) - ({' + '.join(applied) or '0.0'})")
            terms.append(f"{self.relation_pinv(r, n)} * Rx{e}_{n}")
        lines.append(f"lamx{e} = {' + '.join(terms)}")
        return lines

    # ------------------------------------------------------------ functions
    def header(self) -> list[str]:
        P = self.P
        return [(f'"""Generated by clutchsim.network for {P.net.name!r}: '
                 f'{len(P.net.components)} components, {self.n} states.  Do not edit."""'),
                "import math", "", "import numpy as np", "",
                "from clutchsim._jit import jit",
                "from clutchsim.core._borrow import local_empty, local_zeros  # noqa: F401",
                *[f"from {m} import {n}" for m, n in sorted(self.imports)],
                "from clutchsim.network._kernels import lock_solve, table  # noqa: F401",
                "", f"N_STATES = {self.n}", f"N_FE = {len(self.fe)}", ""]

    def rhs(self) -> list[str]:
        return ["@jit", "def rhs(t, y, u, p, dy):", *_ind(self.body(False)), ""]

    def full(self) -> list[str]:
        L = ["@jit", "def _full(t, y, u, p, aux):", f"    dy = local_empty({self.n})"]
        b = self.body(True)
        for c in self.fe:
            e = self.P.fe_index[c.name]
            b += [f"aux[{AUX_W * e}] = s{e}", f"aux[{AUX_W * e + 1}] = sc{e}",
                  f"aux[{AUX_W * e + 2}] = Fe{e}", f"aux[{AUX_W * e + 3}] = fT{e}",
                  f"aux[{AUX_W * e + 4}] = sh{e}"]
            if _lossy(c):
                _i, r, na, _o, _n = self.lossy_meta(c)
                b.append(f"aux[{AUX_W * e + 5}] = fT{e} - {self.relation(r, na)} * lam{r}")
            else:
                b.append(f"aux[{AUX_W * e + 5}] = 0.0")
        for k, ev in enumerate(self.g.events):      # the components' own event functions
            b.append(f"aux[{AUX_W * len(self.fe) + k}] = {ev[2]}")
        return L + _ind(b) + [""]

    def aux_size(self) -> int:
        """Length of ``_full``'s ``aux``: ``AUX_W`` per friction element (slip, scale, stick
        torque, torque, shielded, flange-a torque), then one per component event function."""
        return max(AUX_W * len(self.fe) + len(self.g.events), 1)

    def kinetic_energy(self) -> list[str]:
        """``_ke(y, p)``: the kinetic energy of the nodes [J]."""
        P, asm = self.P, self.asm
        L = ["@jit", "def _ke(y, p):"]
        b = [f"w{n} = {P.node_speed(n)}" for n in range(asm.n_nodes)]
        b.append("return 0.5 * (" + " + ".join(f"{self.node_inertia(n)} * w{n} * w{n}"
                                               for n in range(asm.n_nodes)) + ")")
        return L + _ind(b) + [""]

    def project(self) -> list[str]:
        P, m, nv = self.P, self.m, self.nv
        L = ["@jit", "def _project(y, p):"]
        if not m:
            return L + ["    return", ""]
        b = [f"act = local_zeros({m})", f"rr = local_empty({m})", f"tau = local_empty({m})",
             f"shl = local_empty({m})"]
        for i, c in enumerate(P.sw):
            b.append(f"act[{i}] = 1.0 if {self.lock_test(c)} else 0.0")
            b.append(f"rr[{i}] = " + " + ".join(f"{self.slip_row(i, k)} * y[{k}]" for k in range(nv)))
        b.append(f"lock_solve(p, {P.off_S}, {m}, act, rr, tau, shl)")
        for k in range(nv):
            b.append(f"y[{k}] -= " + " + ".join(f"{self.inv_mass_slip(k, i)} * tau[{i}]" for i in range(m)))
        return L + _ind(b) + [""]

    def element_events(self, c, gname, off):
        """Lines writing element c's event functions into gname[off:...] (aux-based)."""
        e, o, npar, nz, iz = self.fe_meta(c)
        ne = c.model.n_events
        if _lossy(c):
            L = [f"if {self.lock_test(c)}:",
                 f"    lo, up = {self.lossy_bounds(c)}",
                 f"    {gname}[{off}] = {NO_EVENT!r}",
                 (f"    {gname}[{off + 1}] = min(up - aux[{AUX_W * e + 2}], "
                  f"aux[{AUX_W * e + 2}] - lo) + LOSSY_TOL"),
                 "else:",
                 f"    {gname}[{off}] = y[{iz}] * aux[{AUX_W * e}] + 1e-300",
                 f"    {gname}[{off + 1}] = {NO_EVENT!r}"]
        else:
            sc = f"(aux[{AUX_W * e + 1}] if aux[{AUX_W * e + 1}] > 0.0 else {FREE_SCALE!r})"
            L = [(f"{self.kernel(c, 'events')}(p[{o}:{o + npar}], y[{iz}:{iz + nz}], "
                  f"aux[{AUX_W * e}], aux[{AUX_W * e + 2}], {sc}, {gname}[{off}:{off + ne}])")]
        if _lockable(c):
            L.append(f"if {self.lock_test(c)} and aux[{AUX_W * e + 4}] > 0.5:")
            L.append(f"    {gname}[{off + 1}] = {NO_EVENT!r}")
        return L

    def lossy_bounds(self, c) -> str:
        """Expression: (lower, upper) loss a stuck lossy gear holds at its flange-a torque."""
        e = self.P.fe_index[c.name]
        _i, _r, _na, o, nrow = self.lossy_meta(c)
        self.imports.add(("clutchsim.network._kernels", "lossy_bounds"))
        self.imports.add(("clutchsim.network._kernels", "LOSSY_TOL"))
        return f"lossy_bounds(p, {o}, {nrow}, aux[{AUX_W * e + 5}])"

    def event_layout(self):
        """[(kind, object, offset, count)] in event-vector order."""
        out = []
        k = 0
        for c in self.fe:
            ne = c.model.n_events
            if ne:
                out.append(("fe", c, k, ne))
                k += ne
        for ev in self.g.events:
            out.append(("comp", ev, k, 1))
            k += 1
        return out

    def events(self) -> list[str]:
        L = ["@jit", "def events(t, y, u, p, g):"]
        b = [f"aux = local_empty({self.aux_size()})", "_full(t, y, u, p, aux)"]
        k = 0
        for kind, obj, off, _cnt in self.event_layout():
            if kind == "fe":
                b += self.element_events(obj, "g", off)
            else:
                b.append(f"g[{off}] = aux[{AUX_W * len(self.fe) + k}]")
                k += 1
        return L + _ind(b) + [""]

    def reset_fn(self, c) -> list[str]:
        """``_reset_<e>(t, y, u, p, aux, j)``: event j of element c; returns the model's
        reset code after locking/freeing."""
        P = self.P
        e, o, npar, nz, iz = self.fe_meta(c)
        L = ["@jit", f"def _reset_{e}(t, y, u, p, aux, j):"]
        lock = []
        if _lockable(c):
            ilk = P.state_index[(c.name, "locked")]
            lock = [f"y[{ilk}] = 1.0", "ke0 = _ke(y, p)", "_project(y, p)",
                    f"y[{P.y_energy + 5}] += ke0 - _ke(y, p)"]
        if _lossy(c):
            # stop: lock, then look at the torque it must hold; it sticks when that is
            # inside its limits, else it rolls on towards the limit it exceeds (the
            # projection onto zero slip it made is then the start of the new direction)
            fe = f"aux[{AUX_W * e + 2}]"
            b = ["if j == 0:", f"    y[{iz}] = 0.0", *_ind(lock),
                 "    _full(t, y, u, p, aux)",
                 f"    lo, up = {self.lossy_bounds(c)}",
                 f"    if lo - LOSSY_TOL <= {fe} <= up + LOSSY_TOL:",
                 f"        return {RESET_STUCK}",
                 f"    y[{ilk}] = 0.0",
                 f"    y[{iz}] = 1.0 if {fe} > up else -1.0",
                 f"    return {RESET_CHANGED}",
                 "if j == 1:",
                 f"    lo, up = {self.lossy_bounds(c)}",
                 f"    y[{iz}] = 1.0 if up - {fe} <= {fe} - lo else -1.0",
                 f"    y[{ilk}] = 0.0",
                 f"    return {RESET_RELEASED}",
                 f"return {RESET_NONE}"]
            return L + _ind(b) + [""]
        b = [(f"action = {self.kernel(c, 'reset')}(p[{o}:{o + npar}], "
              f"y[{iz}:{iz + nz}], aux[{AUX_W * e}], aux[{AUX_W * e + 2}], "
              f"aux[{AUX_W * e + 1}], j)")]
        if _stick_slip(c):
            # a stop it cannot hold, or a break-away, on a part that other locked elements
            # hold at rest: it stays in its stuck mode unlocked and takes what it can of
            # the torque (up to its capacity), the others the rest
            i = P.sw_index[c.name]
            acts = [f"act[{j}] = 1.0 if {self.lock_test(c2)} else 0.0" for j, c2 in enumerate(P.sw)]
            b += [(f"if ((j == 0 and action == {RESET_CHANGED}) or (j == 1 and action == "
                  f"{RESET_RELEASED})) and aux[{AUX_W * e + 1}] > 0.0:"),
                  f"    act = local_zeros({self.m})", *_ind(acts),
                  f"    act[{i}] = 0.0",
                  f"    if held_by_others(p, {P.off_S}, {self.m}, act, {i}):",
                  f"        y[{iz}] = 0.0"]
            self.imports.add(("clutchsim.network._kernels", "held_by_others"))
        if _lockable(c):
            b += [f"if action == {RESET_STUCK}:", *_ind(lock),
                  f"elif action == {RESET_RELEASED}:",
                  f"    y[{ilk}] = 0.0"]
        b.append("return action")
        return L + _ind(b) + [""]

    def settle(self) -> list[str]:
        P = self.P
        lockable = [c for c in self.fe if _lockable(c)]
        L = ["@jit", "def _settle(t, y, u, p, e0, aux):"]
        if not lockable:
            return L + ["    return", ""]
        b = [f"done = local_zeros({len(self.fe)})", "if e0 >= 0:", "    done[e0] = 1.0",
             "gb = local_empty(4)",
             "vmax = 0.0"]
        b += [f"vmax = max(vmax, abs(y[{k}]))" for k in range(self.nv)]
        b += ["w_tol = 1e-9 * (1.0 + vmax)",
              f"for _it in range({2 * len(lockable) + 1}):",
              "    _full(t, y, u, p, aux)",
              "    hit = -1",
              "    slot = -1"]
        for c in lockable:
            e, _o, _npar, _nz, iz = self.fe_meta(c)
            ilk = P.state_index[(c.name, "locked")]
            ev = self.element_events(c, "gb", 0)
            # (a locked element gets a second look: locking it may have changed what
            # another element transmits, a lossy gear's loss for one, and with it the
            # torque it must hold)
            b += [f"    if hit < 0 and done[{e}] < 1.5 and y[{ilk}] > 0.5:"]
            b += _ind(ev, 2)
            b += ["        if gb[1] < 0.0:",
                  f"            hit = {e}",
                  "            slot = 1",
                  f"    if hit < 0 and done[{e}] < 0.5 and y[{ilk}] <= 0.5:",
                  (f"        if y[{iz}] != 0.0 and y[{iz}] * aux[{AUX_W * e}] <= 0.0 and "
                   f"abs(aux[{AUX_W * e}]) <= w_tol:"),
                  f"            hit = {e}",
                  "            slot = 0"]
            if _stick_slip(c):
                # a holder in its stuck mode, unlocked (whatever happened to it before in
                # this iteration): once no other element holds its part it breaks away, if
                # the torque exceeds its capacity, or locks
                i = P.sw_index[c.name]
                b += [(f"    if hit < 0 and y[{ilk}] <= 0.5 and y[{iz}] == 0.0 and "
                      f"aux[{AUX_W * e + 1}] > 0.0:"),
                      f"        act = local_zeros({self.m})"]
                b += [f"        act[{j}] = 1.0 if {self.lock_test(c2)} else 0.0"
                      for j, c2 in enumerate(P.sw) if j != i]
                b += [f"        if not held_by_others(p, {P.off_S}, {self.m}, act, {i}):"]
                b += _ind(ev, 3)
                # (at its capacity within round-off it breaks away: a torque that has just
                # reached the limit is on its way past it)
                b += [f"            hit = {e}",
                      (f"            slot = 1 if gb[1] < 1e-9 * (1.0 + abs(aux[{AUX_W * e + 2}])) "
                      "else 0")]
                self.imports.add(("clutchsim.network._kernels", "held_by_others"))
        b += ["    if hit < 0:", "        return", "    done[hit] += 1.0"]
        for c in lockable:
            e = P.fe_index[c.name]
            b += [f"    if hit == {e}:", f"        _reset_{e}(t, y, u, p, aux, slot)"]
        return L + _ind(b) + [""]

    def reset(self) -> list[str]:
        """``reset(t, y, u, p, k)``: the action of event ``k``.  Every branch only records
        what follows (``ret``; in ``bk`` the bank to switch to; in ``sk`` the element whose lock
        changed, -1 after a bank switch, -2 for none), so ``_bank`` and ``_settle`` have one
        call site each with a run-time element
        index: called with literal indices, numba compiled it once per element and LLVM
        inlined every copy into ``reset`` (CoupledClutches: 10 of 36 s compiling)."""
        P = self.P
        L = ["@jit", "def reset(t, y, u, p, k):"]
        b = [f"aux = local_empty({self.aux_size()})", "_full(t, y, u, p, aux)",
             "sk = -2", "bk = -1", f"ret = {_CONT}"]
        for kind, obj, off, cnt in self.event_layout():
            if kind == "fe":
                e = P.fe_index[obj.name]
                b += [f"if {off} <= k < {off + cnt}:",
                      f"    action = _reset_{e}(t, y, u, p, aux, k - {off})"]
                if _lockable(obj):
                    b += [f"    if action != {RESET_NONE}:", f"        sk = {e}"]
                none = _PASS if obj.model.smooth_at_events else _CONT
                b += [f"    ret = {_CHANGED} if action != {RESET_NONE} else {none}"]
            elif obj[3] == "bank":
                b += [f"if k == {off}:", f"    bk = {self.banks.index(obj)}",
                      "    sk = -1", f"    ret = {_CHANGED}"]
            else:
                b += [f"if k == {off}:", f"    ret = {_ACTIONS[obj[3]]}"]
        if self.banks:
            b += ["if bk >= 0:", "    _bank(t, y, u, p, bk)"]
        b += ["if sk >= -1:", "    _settle(t, y, u, p, sk, aux)", "return ret"]
        return L + _ind(b) + [""]

    def bank(self) -> list[str]:
        """``_bank(t, y, u, p, b)``: switch to the values of bank ``b`` (a scheduled change,
        e.g. a gear shift).  Bank ``b`` is copied over the active values and derived
        parameters, and the speeds are re-projected: the new independent speeds conserve
        the angular momentum of the old node speeds in the new rigid structure
        (``v = M⁻¹·Nᵀ·diag(J)·w``, an ideal synchroniser), then the locked elements'
        constraints; the kinetic energy that removes is booked in ``W_sync``."""
        P, asm, nv, nn = self.P, self.asm, self.nv, self.asm.n_nodes
        L = ["@jit", "def _bank(t, y, u, p, b):"]
        if not P.banks:
            return L + ["    return", ""]
        base = P.n_params
        body = [f"w{n} = {P.node_speed(n)}" for n in range(nn)]
        body += ["ke0 = _ke(y, p)", f"o = {base} * (b + 1)"]
        # a triggered bank copies its component's values only; a timed one all but those
        # of the triggered components, whose values only their own banks change (so a
        # fault struck before a gear shift stays struck after it)
        trig = [(b, P.value_range[n]) for b, n in enumerate(self.triggered) if n is not None]
        spans, start = [], 0            # what a timed bank copies: all but trig's values
        for lo, hi in sorted(r for _b, r in trig):
            spans += [(start, lo)] if lo > start else []
            start = hi
        spans.append((start, base))
        timed = [ln for lo, hi in spans
                 for ln in (f"for i in range({lo}, {hi}):", "    p[i] = p[o + i]")]
        for b, (lo, hi) in trig:
            body += [f"if b == {b}:", f"    for i in range({lo}, {hi}):",
                     "        p[i] = p[o + i]"]
        if trig:
            body += [f"if {' and '.join(f'b != {b}' for b, _r in trig)}:"]
            timed = ["    " + ln for ln in timed]
        body += timed
        for k in range(nv):
            terms = [f"{P.N(n, k)} * {self.node_inertia(n)} * w{n}" for n in range(nn)
                     if asm.pattern[n][k]]
            body.append(f"h{k} = {' + '.join(terms) or '0.0'}")
        for k in range(nv):
            body.append(f"y[{k}] = " + self.minv_row(k, lambda j: f"h{j}"))
        body += ["_project(y, p)", f"y[{P.y_energy + 5}] += ke0 - _ke(y, p)"]
        return L + _ind(body) + [""]

    def outputs(self) -> list[str]:
        P, asm = self.P, self.asm
        L = ["@jit", "def outputs(t, y, u, p, out):", f"    dy = local_empty({self.n})"]
        b = self.body(True)
        names, units = [], []
        for i, (name, unit, expr, setup) in enumerate(self.g.outputs):
            b += list(setup)
            b.append(f"out[{len(names)}] = {expr}")
            names.append(name)
            units.append(unit)
        for n in range(asm.n_nodes):
            if n == asm.ground or n in asm.free or not asm.J_owner[n]:
                continue
            b.append(f"out[{len(names)}] = w{n}")
            names.append(f"{P.domain.speed}_{asm.node_names[n]}")
            units.append(P.domain.speed_unit)
        b.append(f"out[{len(names)}] = 0.5 * (" + " + ".join(
            f"{self.node_inertia(n)} * w{n} * w{n}" for n in range(asm.n_nodes)) + ")")
        names.append("E_kinetic")
        units.append("J")
        b.append(f"out[{len(names)}] = {' + '.join(self.g.springs) or '0.0'}")
        names.append("E_spring")
        units.append("J")
        if len(self.fe) == 1:               # the only friction element's work: the total
            b.append(f"out[{len(names)}] = y[{P.y_energy + 1}]")
            names.append(f"W_friction_{self.fe[0].name}")
            units.append("J")
        P.output_names, P.output_units = tuple(names), tuple(units)
        return L + _ind(b) + [""]

    def jac(self) -> list[str]:
        P, asm, g, n, nv, m = self.P, self.asm, self.g, self.n, self.nv, self.m
        nn = asm.n_nodes
        L = ["@jit", "def jac(t, y, u, p, J):", f"    dy = local_empty({n})"]
        b = [f"for i in range({n}):", f"    for j in range({n}):", "        J[i, j] = 0.0"]
        b += self.body(False)
        b.append(f"dT = local_zeros(({nn}, {n}))")
        for node, key, expr in g.dtorques:
            b += self.expand("dT", node, key, expr)
        for idx, key, expr in g.dderivs:
            b += self.expand("J", idx, key, expr)
        for nd, idx in P.angle_states:
            b += self.expand("J", idx, ("w", nd), "1.0")
        heat_rows = {}
        for node, key, expr in g.dheats:
            heat_rows.setdefault(node, []).append((key, expr))
        # friction elements: the smooth ones, then the switching ones (whose stick force
        # reads the node torques of the rest: dTb, before theirs are added)
        stick = self.stick_readers()
        for c in sorted(self.fe, key=lambda c: c.name in P.sw_index):
            e, _o, _npar, nz, iz = self.fe_meta(c)
            gv = P.slips[c.name]
            if stick and c is next(c2 for c2 in self.fe if c2.name in P.sw_index):
                b.append(f"dTb = local_empty(({asm.n_nodes}, {n}))")
                b += [f"for nd in range({asm.n_nodes}):", f"    for col in range({n}):",
                      "        dTb[nd, col] = dT[nd, col]"]
            if _lossy(c):
                # loss power L·w: the L·dw part here, dL·w in the column loop below
                for nd in np.flatnonzero(gv):
                    for fr in self.work_rows(c):
                        b += self.expand("J", fr, ("w", int(nd)),
                                         f"fT{e} * {float(gv[nd])!r}")
                continue
            cond = f"not locked{e}" if c.name in P.sw_index else "True"
            blk = [f"Jz{e} = local_zeros(({nz}, {nz + 1}))", f"dF{e} = local_zeros({nz + 3})",
                   f"dz{e} = local_zeros({max(nz, 1)})",
                   f"{self.fcall('friction_jacobian', c, f'Fe{e}', dz=f'dz{e}[:{nz}]', extra=f', Jz{e}, dF{e}')}",
                   f"dTs{e} = dF{e}[{nz}]"]
            if getattr(c, "has_drag", False):
                th = f"math.tanh(s{e})"
                blk.append(f"dTs{e} += p[{P.slot[(c.name, 'drag')]}] * (1.0 - {th} * {th})")
            blk.append(f"sq{e} = 1.0 if fT{e} * s{e} > 0.0 else (-1.0 if fT{e} * s{e} < 0.0 "
                       "else 0.0)")
            # partials of the element torque: list of (key, expr)
            parts = [(("w", int(nd)), f"{float(gv[nd])!r} * dTs{e}") for nd in np.flatnonzero(gv)]
            parts += [(("y", iz + j), f"dF{e}[{j}]") for j in range(nz)]
            parts += [(key, f"dF{e}[{nz + 2}] * ({expr})") for key, expr in c.scale_partials_of(e)]
            for nd in np.flatnonzero(gv):
                for key, expr in parts:
                    blk += self.expand("dT", int(nd), key, f"{-float(gv[nd])!r} * {expr}")
            # friction power fT·s
            for fr in self.work_rows(c):
                for key, expr in parts:
                    blk += self.expand("J", fr, key, f"({expr}) * s{e}")
                for nd in np.flatnonzero(gv):
                    blk += self.expand("J", fr, ("w", int(nd)),
                                       f"fT{e} * {float(gv[nd])!r}")
            # own state rows
            for i in range(nz):
                for j in range(nz):
                    blk.append(f"J[{iz + i}, {iz + j}] += Jz{e}[{i}, {j}]")
                for nd in np.flatnonzero(gv):
                    blk += self.expand("J", iz + i, ("w", int(nd)),
                                       f"{float(gv[nd])!r} * Jz{e}[{i}, {nz}]")
            # heat q = |T s|
            for node, share_key in c.heat_shares():
                share = f"p[{P.slot[(c.name, share_key)]}]"
                hrows = heat_rows.setdefault(node, [])
                for key, expr in parts:
                    hrows.append((key, f"{share} * sq{e} * ({expr}) * s{e}", cond))
                for nd in np.flatnonzero(gv):
                    hrows.append((("w", int(nd)),
                                  f"{share} * sq{e} * fT{e} * {float(gv[nd])!r}", cond))
            if getattr(c, "wear", None) is not None:     # wear rate kw(θ)·|T s|
                wr, th = P.state_index[(c.name, "wear")], P.state_index[(c.heat[0][0], "theta")]
                for key, expr in parts:
                    blk += self.expand("J", wr, key, f"kw{e} * sq{e} * ({expr}) * s{e}")
                for nd in np.flatnonzero(gv):
                    blk += self.expand("J", wr, ("w", int(nd)),
                                       f"kw{e} * sq{e} * fT{e} * {float(gv[nd])!r}")
                blk.append(f"J[{wr}, {th}] += dkw{e} * q{e}")
            b.append(f"if {cond}:")
            b += _ind(blk)
            if cond != "True":
                # locked: its torque is a constraint torque; the friction power τ·w keeps
                # the τ·dw part (w itself is held at 0)
                els = []
                for nd in np.flatnonzero(gv):
                    for fr in self.work_rows(c):
                        els += self.expand("J", fr, ("w", int(nd)),
                                           f"fT{e} * {float(gv[nd])!r}")
                if els:
                    b += ["else:", *_ind(els)]
        b += self.stick_columns(stick, heat_rows)
        # generalised: dF = N^T dT, then M^-1 and the lock projection
        b.append(f"dG = local_zeros(({max(nv, 1)}, {n}))")
        for k in range(nv):
            for nd in range(nn):
                if asm.pattern[nd][k]:
                    b.append(f"for col in range({n}):")
                    b.append(f"    dG[{k}, col] += {P.N(nd, k)} * dT[{nd}, col]")
        b.append(f"for col in range({n}):")
        inner = []
        for k in range(nv):
            inner.append(f"da{k} = " + self.minv_row(k, lambda j: f"dG[{j}, col]"))
        if m:
            for i in range(m):
                inner.append(f"rr[{i}] = " + " + ".join(f"{self.slip_row(i, k)} * da{k}"
                                                        for k in range(nv)))
            inner.append(f"lock_solve(p, {P.off_S}, {m}, act, rr, tau, shl)")
            for k in range(nv):
                inner.append(f"da{k} -= " + " + ".join(f"{self.inv_mass_slip(k, i)} * tau[{i}]"
                                                       for i in range(m)))
        inner += self.lossy_columns()
        for k in range(nv):
            inner.append(f"J[{k}, col] = da{k}")
        if not inner:
            inner.append("pass")
        b += _ind(inner)
        acc_row = {acc: P.y_energy + i for i, (_n, acc) in enumerate(ENERGY)}
        for acc, key, expr in g.dpowers:
            b += self.expand("J", acc_row[acc], key, expr)
        for c in P.thermal:
            idx = P.state_index[(c.name, "theta")]
            cap = f"p[{P.slot[(c.name, 'capacity')]}]"
            for entry in heat_rows.get(c.name, []):
                key, expr = entry[0], entry[1]
                cond = entry[2] if len(entry) > 2 else "True"
                lines = self.expand("J", idx, key, f"({expr}) / {cap}")
                if cond != "True" and lines:    # (a partial by a grounded speed: none)
                    b.append(f"if {cond}:")
                    b += _ind(lines)
                else:
                    b += lines
        return L + _ind(b) + [""]

    def stick_readers(self) -> list:
        """The switching elements whose force can read their stick force ``Fe`` in ``rhs``
        (a coulomb-robust element stuck but not locked, Karnopp in its window: the force is
        ``Fe`` clipped to the capacity), when the plant has no lossy gear (whose rolling
        loss enters ``Fe`` through a loop :meth:`stick_columns` does not differentiate)."""
        P = self.P
        if any(_lossy(c) for c in P.sw):
            return []
        return [c for c in P.sw if not _lockable(c) or _stick_slip(c)]

    def stick_columns(self, stick, heat_rows) -> list[str]:
        """The partials of the stick force ``Fe`` of each element of ``stick`` (where its
        force reads it: ``dF/dFe`` ≠ 0), chained into its torque's rows: node torques,
        friction work, heat and wear.  ``Fe_i = [S_AA⁻¹·(B_A·M⁻¹·G' + F1_i·S_Ai)]_i``
        (the switch block of :meth:`body`), ``G' = Nᵀ·T_b − Σ_j B_j·F1_j``: ``T_b`` the node
        torques of everything but the switching elements (``dTb``), ``F1_j`` their forces
        at ``Fe = 0`` (``d1_<e>``: the model's Jacobian called there)."""
        P, asm, n, nv, m = self.P, self.asm, self.n, self.nv, self.m
        if not stick:
            return []
        nn = asm.n_nodes
        L = []
        for c in P.sw:                      # the pass-1 forces' partials
            e, _o, _npar, nz, _iz = self.fe_meta(c)
            L.append(f"d1_{e} = local_zeros((1, {n}))")
            blk = [f"Jz1_{e} = local_zeros(({nz}, {nz + 1}))",
                   f"dF1_{e} = local_zeros({nz + 3})", f"dz1_{e} = local_zeros({max(nz, 1)})",
                   self.fcall("friction_jacobian", c, "0.0", dz=f"dz1_{e}[:{nz}]",
                              extra=f", Jz1_{e}, dF1_{e}"),
                   f"dT1_{e} = dF1_{e}[{nz}]"]
            if getattr(c, "has_drag", False):
                th = f"math.tanh(s{e})"
                blk.append(f"dT1_{e} += p[{P.slot[(c.name, 'drag')]}] * (1.0 - {th} * {th})")
            _e, _o, _np, nz, iz = self.fe_meta(c)
            gv = P.slips[c.name]
            parts = [(("w", int(nd)), f"{float(gv[nd])!r} * dT1_{e}")
                     for nd in np.flatnonzero(gv)]
            parts += [(("y", iz + j), f"dF1_{e}[{j}]") for j in range(nz)]
            parts += [(key, f"dF1_{e}[{nz + 2}] * ({expr})")
                      for key, expr in c.scale_partials_of(e)]
            for key, expr in parts:
                blk += self.expand(f"d1_{e}", 0, key, expr)
            L += [f"if not locked{e}:"] + _ind(blk)
        for c in stick:
            e, _o, _npar, nz, _iz = self.fe_meta(c)
            i = P.sw_index[c.name]
            gv = P.slips[c.name]
            col = []
            for k in range(nv):
                base = " + ".join(f"{P.N(nd, k)} * dTb[{nd}, col]" for nd in range(nn)
                                  if asm.pattern[nd][k]) or "0.0"
                minus = " + ".join(f"(0.0 if locked{P.fe_index[c2.name]} else {self.slip_row(j, k)} * "
                                   f"d1_{P.fe_index[c2.name]}[0, col])"
                                   for j, c2 in enumerate(P.sw))
                col.append(f"gq{k} = {base} - ({minus})")
            for k in range(nv):
                col.append(f"xq{k} = " + self.minv_row(k, lambda j: f"gq{j}"))
            for j, c2 in enumerate(P.sw):
                e2 = P.fe_index[c2.name]
                col.append(f"act[{j}] = 1.0 if ({j} == {i} or locked{e2}) else 0.0")
                col.append(f"rr[{j}] = " + " + ".join(f"{self.slip_row(j, k)} * xq{k}"
                                                      for k in range(nv))
                           + f" + d1_{e}[0, col] * p[{P.off_S + j * m + i}]")
            col.append(f"lock_solve(p, {P.off_S}, {m}, act, rr, tau, shl)")
            col.append(f"vq = dFe{e} * tau[{i}]")
            for nd in np.flatnonzero(gv):
                col.append(f"dT[{int(nd)}, col] += {-float(gv[nd])!r} * vq")
            for fr in self.work_rows(c):
                col.append(f"J[{fr}, col] += vq * s{e}")
            for node, share_key in c.heat_shares():
                th = P.state_index[(node, "theta")]
                cap = f"p[{P.slot[(node, 'capacity')]}]"
                share = f"p[{P.slot[(c.name, share_key)]}]"
                col.append(f"J[{th}, col] += {share} * sq{e} * vq * s{e} / {cap}")
            if getattr(c, "wear", None) is not None:
                wr = P.state_index[(c.name, "wear")]
                col.append(f"J[{wr}, col] += kw{e} * sq{e} * vq * s{e}")
            L += [f"dFe{e} = dF{e}[{nz + 1}] if not locked{e} else 0.0",
                  f"if dFe{e} != 0.0:", f"    for col in range({n}):", *_ind(col, 2)]
        # the lock projection of the columns below marks the locked elements again
        L += [f"act[{j}] = 1.0 if locked{P.fe_index[c2.name]} else 0.0"
              for j, c2 in enumerate(P.sw)]
        return L

    def jac_pattern(self, jac_lines) -> np.ndarray:
        """Where ``jac`` can write a non-zero: a boolean ``(n, nd)`` pattern over the
        implicit columns (``nd`` states before the quadratures), read off the statements of
        its lines (:meth:`jac`).  ``J[i, j] +=`` with literal indices is entry ``(i, j)``; a generalised
        acceleration's row ``J[k, col] = da_k`` holds the columns of the node torques
        ``dT[node, j]`` that reach coordinate ``k`` through ``N`` and ``M⁻¹``; the lock
        projection and rolling lossy gears couple every acceleration (their union).  Any
        other write to ``J`` raises, so that a change to ``jac`` cannot leave the pattern
        (and the elimination generated from it) behind."""
        P, asm, n, nv = self.P, self.asm, self.n, self.nv
        nd = n - P.n_quadratures
        pat = np.zeros((n, n), dtype=bool)
        dT = np.zeros((asm.n_nodes, n), dtype=bool)
        col_rows = set()
        dT_any: set = set()
        for line in jac_lines:
            for stmt in line.split("\n"):
                stmt = stmt.strip()
                if stmt.startswith("dT["):
                    m = re.match(r"dT\[(\d+), (\d+)\] \+= ", stmt)
                    if m is None:
                        m = re.match(r"dT\[(\d+), col\] \+= ", stmt)
                        if m is None:
                            raise AssertionError(f"jac_pattern: unknown write {stmt!r}")
                        dT_any.add(int(m[1]))    # a stick force's column (any of dT's)
                        continue
                    dT[int(m[1]), int(m[2])] = True
                    continue
                if not re.search(r"\bJ\[", stmt) or stmt == "J[i, j] = 0.0":
                    continue
                m = re.match(r"J\[(\d+), (\d+)\] \+= ", stmt)
                if m is not None:
                    pat[int(m[1]), int(m[2])] = True
                    continue
                m = re.match(r"J\[(\d+), col\] (\+)?= ", stmt)
                if m is None:
                    raise AssertionError(f"jac_pattern: unknown write {stmt!r}")
                col_rows.add(int(m[1]))
        # a stick force reads every node torque's columns (and the pass-1 forces', which
        # are among them): its rows get their union
        if dT_any:
            union = dT.any(axis=0)
            for r in dT_any:
                dT[r] |= union
        # the accelerations: dG = Nᵀ·dT, da = M⁻¹·dG (as patterns)
        dG = np.array(asm.pattern, dtype=int).T @ dT.astype(int) > 0
        da = self.mpat.astype(int) @ dG.astype(int) > 0
        lossy = any(_lossy(c) for c in P.sw)
        if self.m or lossy:
            every = da.any(axis=0) | dT.any(axis=0)
            if lossy:
                every[:nv] = True
            da[:] = every
        for r in col_rows:
            pat[r] |= da[r] if r < nv else da.any(axis=0)
        if pat[:, nd:].any():
            raise AssertionError("jac_pattern: a quadrature column is written")
        return pat[:, :nd]

    def linear(self, jac_lines) -> list[str]:
        """``FACTOR_SIZE``, ``factor`` and ``solve`` of the iteration matrix for the
        pattern of ``jac_lines`` (:meth:`jac_pattern`, :mod:`clutchsim.network.elimination`),
        or nothing when straight-line code would not beat the dense inverse."""
        el = elimination_source(self.jac_pattern(jac_lines), self.n)
        if el is None:
            return []
        return ["#: floats of the factors ``factor`` writes", f"FACTOR_SIZE = {el.size}", "",
                *el.lines]

    def lossy_columns(self) -> list[str]:
        """Column ``col`` of the Jacobian through rolling lossy gears: ``dL = dL/dT_a0 ·
        dT_a0 + dL/dw · dw`` (``dT_a0`` from the column's accelerations and torques
        without the loss, as in :meth:`lossy_roll`), then ``da += dL·xu``."""
        P, asm, nv, nn = self.P, self.asm, self.nv, self.asm.n_nodes
        lossy = [c for c in P.sw if _lossy(c)]
        if not lossy:
            return []
        L = [f"dTc = local_empty({nn})"] + [f"dTc[{nd}] = dT[{nd}, col]" for nd in range(nn)]
        for c in lossy:
            e = P.fe_index[c.name]
            i, r, na, _o, _n = self.lossy_meta(c)
            gi = P.slips[c.name]
            b = []
            terms = []
            for nd in range(nn):
                al = " + ".join(f"{P.N(nd, k)} * da{k}" for k in range(nv)
                                if asm.pattern[nd][k]) or "0.0"
                locks = [f"{-float(P.slips[c2.name][nd])!r} * (tau[{j}] if "
                         f"locked{P.fe_index[c2.name]} else 0.0)"
                         for j, c2 in enumerate(P.sw) if P.slips[c2.name][nd] != 0.0]
                b.append(f"dR{nd} = {self.node_inertia(nd)} * ({al}) - (dTc[{nd}]"
                         + "".join(f" + {x}" for x in locks) + ")")
                terms.append(f"{self.relation_pinv(r, nd)} * dR{nd}")
            b.append(f"dlx = {' + '.join(terms)}")
            b.append(f"dL = dLT{e} * (-{self.relation(r, na)} * dlx) + (dLs{e} * "
                     f"p[{P.off_B + i * nv} + col] if col < {nv} else 0.0)")
            for k in range(nv):
                b.append(f"da{k} += dL * xu{e}_{k}")
            b += [f"J[{fr}, col] += dL * s{e}" for fr in self.work_rows(c)]
            for nd in np.flatnonzero(gi):
                b.append(f"dTc[{int(nd)}] += {-float(gi[nd])!r} * dL")
            L += [f"if not locked{e}:"] + _ind(b)
        return L

    def module(self) -> str:
        parts = self.rhs() + self.full() + self.kinetic_energy() + self.project()
        for c in self.fe:
            if c.model.n_events:
                parts += self.reset_fn(c)
        jac = self.jac()
        parts += (self.settle() + self.bank() + self.events() + self.reset() + self.outputs()
                  + jac + self.linear(jac))
        parts = self.header() + parts       # the header imports what the functions use
        P = self.P
        names, dirs = [], []
        P.event_templates = {}
        for kind, obj, _off, _cnt in self.event_layout():
            if kind == "fe":
                names += [f"{obj.name}: {x}" for x in obj.model.event_names()]
                dirs += [int(d) for d in obj.model.event_directions()]
            else:
                P.event_templates[len(names)] = (obj[0], obj[4])
                names.append(obj[0])
                dirs.append(obj[1])
        P.event_names, P.event_directions = tuple(names), tuple(dirs)
        return "\n".join(parts) + "\n"


def render(plan, g) -> str:
    return _PlantRenderer(plan, g).module()
