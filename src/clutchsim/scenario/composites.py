"""Components a scenario writes as one table and the network builds from several: a
``gearbox`` with a ``synchronizer`` table.

A gearbox's shifts are ideal by default: the ratio changes at the shift's time and an
ideal synchroniser joins the two sides with their angular momentum conserved (``W_sync``).
With a ``synchronizer`` table each gear is its own path through the box, as a constant-mesh
manual or automated gearbox is built: on the input shaft the gear's pinion (an
``ideal_gear`` of the gear's ratio) drives its idler gear (an ``inertia`` of ``J_idler``,
or a massless node), which a single-sided ``synchronizer`` (cone, blocker, dog) joins to
the output shaft; the final drive (an ``ideal_gear``, or a ``lossy_gear`` with the
gearbox's efficiencies) follows.  The engaged gear's sleeve is held in with ``force`` from
the start; a shift at ``time`` to gear g takes the engaged sleeve out at ``time`` (the
force falls to 0: the dog is released), and pushes gear g's sleeve in with ``force`` at
``time + neutral``: its cone synchronises the input side (the clutch disc, the input
shaft, the idlers) with the output, the blocker keeps the dog out while the slip is above
``w_sync``, and the dog engages inside it.  Open the clutch around a shift, as with the
ideal shift.

This is a pure rewrite of the document's tables (as :mod:`.chain_format` is for chain
files): the generated tables are checked by the components' own declarations, and
:meth:`Expansion.source_key` sends an error about a generated table back to the key of
the gearbox the user wrote.  Generated names: ``<gearbox>_gear<k>``, ``<gearbox>_idler<k>``,
``<gearbox>_sync<k>`` and the sleeve force signals ``<gearbox>_sleeve<k>`` [N]; the
gearbox's own name is its final drive.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

__all__ = ["SYNCHRONIZER_KEYS", "Expansion", "expand", "has_composites", "synchronizer_keys"]

#: the keys of a gearbox's ``synchronizer`` table that are the gearbox's own (the others
#: are those of the ``synchronizer`` component, given to each gear's synchroniser):
#: key -> (unit, doc, lowest value, lowest excluded, default or None for required)
SYNCHRONIZER_KEYS = {
    "force": ("N", ("Sleeve force that holds the engaged gear in and presses the cone of "
                    "the gear shifted to; > F_block (else the sleeve never passes the "
                    "blocker)."), 0.0, True, None),
    "neutral": ("s", ("Time in neutral between the sleeve out of the old gear and the "
                      "sleeve force on the new gear's cone (the sleeve passes through "
                      "neutral: not both at one instant)."), 0.0, True, 0.05),
    "J_idler": ("kg·m²", ("Inertia of each idler gear (0: massless; > 0 needs the "
                          "gearbox's flange a at an inertia, whose initial speed sets the "
                          "idlers')."), 0.0, False, 0.0),
}
#: keys of the ``synchronizer`` component a gearbox sets itself for each gear
_SET_BY_GEARBOX = ("name", "type", "command", "side", "engaged0")


def synchronizer_keys() -> tuple:
    """The keys of a gearbox's ``synchronizer`` table (:class:`~.schema.Key`): its own,
    then the ``synchronizer`` component's (generated from its declaration)."""
    from .schema import Key, component_types
    own = tuple(Key(k, "number", doc, unit, required=default is None, low=low,
                    strict=strict, high=1e6)
                for k, (unit, doc, low, strict, default) in SYNCHRONIZER_KEYS.items())
    return own + tuple(k for k in component_types()["synchronizer"]
                       if k.name not in _SET_BY_GEARBOX)


@dataclass(frozen=True)
class Expansion:
    """A document with its composite tables replaced by the components they stand for.

    Attributes
    ----------
    data : dict
        The document (``component`` and ``network`` tables).
    inputs : dict
        Generated input signals: name -> formula text.
    tables : dict
        ``component[j]`` -> the key path of the table it was made from (``component[4].
        synchronizer``): a key inside it keeps its name.
    whole : dict
        ``component[j]`` -> ``{its key: the key that made it}`` (a gear's ``ratio`` ->
        ``component[4].ratios``); its other keys -> the ``"*"`` entry.
    """

    data: dict
    inputs: dict = field(default_factory=dict)
    tables: dict = field(default_factory=dict)
    whole: dict = field(default_factory=dict)

    def source_key(self, key: str) -> str:
        """The key the user wrote for a key of :attr:`data` (``component[9].R_m`` ->
        ``component[4].synchronizer.R_m``); other keys as they are."""
        m = re.match(r"(component\[\d+\])\.?([^.\[]*)(.*)", key)
        if not m:
            return key
        head, first, rest = m.groups()
        if head in self.whole:
            keys = self.whole[head]
            return keys.get(first, keys["*"])
        if head in self.tables:
            return self.tables[head] + (f".{first}" if first else "") + rest
        return key


def has_composites(data: dict) -> bool:
    """Does the document (network or chain tables) hold a table :func:`expand` replaces?"""
    return any(t.get("type") == "gearbox" and "synchronizer" in t
               for table in ("component", "coupling") for t in data.get(table, [])
               if isinstance(t, dict))


def expand(data: dict, fail) -> Expansion:
    """The document ``data`` (network tables: ``component``, ``network``) with each
    ``gearbox`` that has a ``synchronizer`` table replaced by its gears, idlers,
    synchronisers and final drive (see the module docstring).  ``fail(problem, key)``
    raises for a table that cannot be expanded, with the key of ``data``."""
    if not has_composites(data):
        return Expansion(data)
    comps = list(data.get("component", []))
    conns = [list(c) for c in data.get("network", {}).get("connect", [])]
    names = {t.get("name") for t in comps}
    inputs, tables, whole = {}, {}, {}
    user_inputs = data.get("inputs", {})
    for i, t in enumerate(list(comps)):
        if t.get("type") != "gearbox" or "synchronizer" not in t:
            continue
        key = f"component[{i}]"
        gearbox = _Gearbox(t, key, fail)
        made = gearbox.components(_speed_at(comps, conns, f"{gearbox.name}.a"), conns)
        for table, source in made[1:]:
            clash = table["name"]
            if clash in names:
                j = next((j for j, c in enumerate(comps) if c.get("name") == clash), i)
                fail(f"= {clash!r} is a name that gearbox {gearbox.name!r} gives a part of "
                     "its synchronizers: rename this component", f"component[{j}].name")
            names.add(clash)
            j = f"component[{len(comps)}]"
            (whole if isinstance(source, dict) else tables)[j] = source
            comps.append(table)
        comps[i] = made[0][0]
        whole[key] = made[0][1]
        for name, text in gearbox.sleeves().items():
            if name in user_inputs:
                fail(f"is the sleeve force signal that gearbox {gearbox.name!r} makes for its "
                     "synchronizer: rename this input", f"inputs.{name}")
            inputs[name] = text
        conns = gearbox.connections(conns, fail)
    out = dict(data)
    out["component"] = comps
    out["network"] = {**data.get("network", {}), "connect": conns}
    return Expansion(out, inputs, tables, whole)


class _Gearbox:
    """One gearbox table with a ``synchronizer`` table, checked."""

    def __init__(self, t: dict, key: str, fail):
        self.t, self.key, self.fail = t, key, fail
        self.name = str(t.get("name"))
        sync = t["synchronizer"]
        at = f"{key}.synchronizer"
        if not isinstance(sync, dict):
            fail(f"must be a table {{force = N, R_m = m, alpha = °, w_sync = rad/s, F_block = "
                 f"N, friction = {{...}}}}, got {sync!r}", at)
        from .schema import check_table
        check_table(sync, synchronizer_keys(), at, fail)
        own = {k: float(sync.get(k, v[-1])) for k, v in SYNCHRONIZER_KEYS.items()}
        self.sync = {k: v for k, v in sync.items() if k not in SYNCHRONIZER_KEYS}
        self.force, self.neutral, self.J_idler = own["force"], own["neutral"], own["J_idler"]
        block = sync.get("F_block")
        if isinstance(block, (int, float)) and not self.force > block:
            fail(f"= {self.force:g} N must be > F_block = {block:g} N: the sleeve passes the "
                 "blocker only with a force above F_block", f"{at}.force")
        ratios = t.get("ratios")
        if not isinstance(ratios, list) or not ratios:
            fail("must list the gear ratios, gear 1 first", f"{key}.ratios")
        self.ratios = ratios
        self.gear = t.get("gear", 1)
        n = len(ratios)
        if isinstance(self.gear, bool) or self.gear not in range(1, n + 1):
            fail(f"gear {self.gear!r} does not exist: this gearbox has {n} gears (1..{n})",
                 f"{key}.gear")
        if t.get("drag_torque", 0.0) != 0.0:
            fail(f"= {t['drag_torque']!r} N·m: a gearbox with a synchronizer has no drag "
                 "torque (its drag is referred to the input, which each gear reaches through "
                 "its own ratio); put the drag in the input inertia's bearing_damping",
                 f"{key}.drag_torque")
        self.shifts = []
        engaged = int(self.gear)
        last = -math.inf
        for j, s in enumerate(t.get("shifts", [])):
            where = f"{key}.shifts[{j}]"
            if not isinstance(s, dict):
                fail(f"must be a table {{time = s, gear = k}}, got {s!r}", where)
            time, gear = s.get("time"), s.get("gear")
            if isinstance(time, bool) or not isinstance(time, (int, float)) or not time > 0.0:
                fail(f"time = {time!r} must be a time > 0 s", f"{where}.time")
            if isinstance(gear, bool) or gear not in range(1, n + 1):
                fail(f"gear {gear!r} does not exist: this gearbox has {n} gears (1..{n})",
                     f"{where}.gear")
            if not time > last:
                fail(f"time = {time:g} s must be later than the previous shift's sleeve force "
                     f"on the new gear at {last:g} s (a shift takes neutral = "
                     f"{self.neutral:g} s)", f"{where}.time")
            if gear == engaged:
                fail(f"gear {gear} is engaged already at {time:g} s", f"{where}.gear")
            self.shifts.append((float(time), engaged, int(gear)))
            engaged, last = int(gear), float(time) + self.neutral

    def name_of(self, what: str, k: int) -> str:
        return f"{self.name}_{what}{k}"

    def sleeves(self) -> dict:
        """Each gear's sleeve force signal [N] as formula text."""
        f = repr(self.force)
        terms = {k: [f] if k == self.gear else [] for k in range(1, len(self.ratios) + 1)}
        for time, old, new in self.shifts:
            terms[old].append(f"- step({time!r}, {f})")
            terms[new].append(f"+ step({float(f'{time + self.neutral:.12g}')!r}, {f})")
        return {self.name_of("sleeve", k): (" ".join(v).lstrip("+ ") if v else "0.0")
                for k, v in terms.items()}

    def components(self, speed_a, conns) -> list:
        """``[(table, source)]``: the final drive (the gearbox's own slot) first, then each
        gear's pinion, idler and synchroniser.  ``source``: the key path of the table a
        component's keys come from, or ``{key: source key, "*": source key}``."""
        t, key = self.t, self.key
        eta = t.get("efficiency", 1.0)
        eta_r = t.get("efficiency_reverse", eta)
        final = {"name": self.name, "ratio": t.get("final_drive", 1.0)}
        source = {"ratio": f"{key}.final_drive", "*": key}
        if eta == 1.0 and eta_r == 1.0:
            final["type"] = "ideal_gear"
        else:
            final.update(type="lossy_gear", loss_table={
                "speed": [0.0], "eta_mf1": [eta], "eta_mf2": [eta_r],
                "tau_bf1": [0.0], "tau_bf2": [0.0]})
            source["loss_table"] = f"{key}.efficiency"
        out = [(final, source)]
        for k, ratio in enumerate(self.ratios, start=1):
            out.append(({"type": "ideal_gear", "name": self.name_of("gear", k), "ratio": ratio},
                        {"ratio": f"{key}.ratios[{k - 1}]", "*": f"{key}.ratios"}))
            if self.J_idler > 0.0:
                if speed_a is None:
                    self.fail("J_idler > 0 needs the gearbox's flange a connected to an "
                              "inertia (its initial speed sets the idlers'); connect it to "
                              "one, or give J_idler = 0", f"{key}.synchronizer.J_idler")
                w0 = speed_a / ratio if isinstance(ratio, (int, float)) and ratio else 0.0
                out.append(({"type": "inertia", "name": self.name_of("idler", k),
                             "J": self.J_idler, "omega0": w0},
                            {"*": f"{key}.synchronizer.J_idler"}))
            sync = {"type": "synchronizer", "name": self.name_of("sync", k),
                    "command": self.name_of("sleeve", k), **self.sync}
            if k == self.gear:
                sync["engaged0"] = 1
            out.append((sync, f"{key}.synchronizer"))
        return out

    def connections(self, conns: list, fail) -> list:
        """``conns`` with the gearbox's flange a at every pinion and its other flanges'
        paths through the gears, idlers and synchronisers to the final drive."""
        name = self.name
        if any(f"{name}.support" in c for c in conns):
            fail(f"{name}.support is connected: a gearbox with a synchronizer has its "
                 "housing grounded (leave the support out)", "network.connect")
        first = f"{self.name_of('gear', 1)}.a"
        out = [[first if x == f"{name}.a" else x for x in c] for c in conns]
        n = len(self.ratios)
        if n > 1:
            out.append([f"{self.name_of('gear', k)}.a" for k in range(1, n + 1)])
        for k in range(1, n + 1):
            gear, sync = self.name_of("gear", k), self.name_of("sync", k)
            if self.J_idler > 0.0:
                idler = self.name_of("idler", k)
                out += [[f"{gear}.b", f"{idler}.a"], [f"{idler}.b", f"{sync}.a"]]
            else:
                out.append([f"{gear}.b", f"{sync}.a"])
        out.append([*(f"{self.name_of('sync', k)}.b" for k in range(1, n + 1)), f"{name}.a"])
        return out


def _speed_at(comps: list, conns: list, flange: str):
    """The initial speed of the inertia whose flange shares a connection with ``flange``
    (None when no inertia is there)."""
    inertias = {t.get("name"): t for t in comps if t.get("type") == "inertia"}
    for c in conns:
        if flange in c:
            for x in c:
                owner = x.partition(".")[0]
                if owner in inertias:
                    w = inertias[owner].get("omega0", 0.0)
                    return float(w) if isinstance(w, (int, float)) else 0.0
    return None
