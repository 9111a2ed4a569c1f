"""The chain format, read as a network: ``[[inertia]]``/``[[coupling]]``/``[[brake]]``/
``[engine]``/``[vehicle]``/``[[thermal]]`` tables rewritten into ``[[component]]`` tables
and ``[network] connect`` (the table "Chain files" of ``docs/network.md``).

A pure rewrite of the document's tables (names only, no network objects): the network
components' declarations check and document every key, and :class:`Rewrite` keeps the key
map that sends an error about a generated table back to the chain key path it came from.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

__all__ = ["CHAIN_ONLY", "CHAIN_TABLES", "COUPLING_TYPES", "KIND_OF", "Rewrite",
           "is_chain", "nodes", "rewrite"]

#: the tables of the chain format, in the order their components are listed
CHAIN_TABLES = ("inertia", "coupling", "brake", "engine", "vehicle", "thermal")

#: coupling ``type`` -> network component type
COUPLING_TYPES = {"clutch": "clutch", "one_way_clutch": "one_way_clutch",
                  "spring_damper": "spring_damper", "gear": "ideal_gear",
                  "lossy_gear": "lossy_gear", "gearbox": "gearbox"}

#: the other chain tables -> network component type
KIND_OF = {"inertia": "inertia", "brake": "brake", "engine": "engine",
           "vehicle": "vehicle", "thermal": "thermal_node"}

#: couplings that are gears themselves (their ``ratio`` is their own parameter)
_GEARS = ("gear", "lossy_gear", "gearbox")

#: fixed component names of the tables that are not arrays
_NAMES = {"engine": "engine_torque", "vehicle": "vehicle"}

#: keys of the chain format that become structure, not a parameter: (table, coupling
#: types or None for all) -> {key: (network component type, the key it becomes there,
#: doc, required)}; a ``node`` becomes a connection (type and key None: a string)
CHAIN_ONLY = {
    ("inertia", None): {"load": ("torque", "input", ("Input signal applied as a torque on "
                                                    "this inertia [N·m] (a `torque` "
                                                    "component on it)."), False)},
    ("coupling", ("clutch", "one_way_clutch", "spring_damper")): {
        "ratio": ("ideal_gear", "ratio", ("Ideal ratio on the input side (an `ideal_gear` "
                                          "between inertia k and the coupling; 1: none)."),
                  False)},
    ("brake", None): {"node": (None, None, "Inertia the brake acts on.", True)},
    ("engine", None): {"node": (None, None, "Inertia the engine drives.", True)},
}


def is_chain(data: dict) -> bool:
    """Is ``data`` a chain document (any of :data:`CHAIN_TABLES`)?"""
    return any(t in data for t in CHAIN_TABLES)


def nodes(data: dict) -> list[tuple[str, object]]:
    """``(key path, value)`` of every ``node`` of a chain document (a brake's, the
    engine's): each must name an inertia."""
    out = [(f"brake[{i}].node", t.get("node")) for i, t in enumerate(data.get("brake", []))]
    if "engine" in data:
        out.append(("engine.node", data["engine"].get("node")))
    return out


@dataclass(frozen=True)
class Rewrite:
    """A chain document as a network document, and the way back for key paths.

    Attributes
    ----------
    data : dict
        The document with ``component`` and ``network`` tables instead of the chain's.
    tables : dict
        ``component[j]`` -> the chain table it came from (``coupling[1]``, ``engine``):
        a key inside it keeps its name (``component[3].c`` -> ``coupling[1].c``).
    whole : dict
        ``component[j]`` -> the one chain key that made it (``inertia[0].load`` for a load's
        torque source, ``coupling[2].ratio`` for a coupling's own ratio): every key
        inside it is that key.
    connect : str
        The chain key that stands for ``network.connect`` (the couplings).
    """

    data: dict
    tables: dict = field(default_factory=dict)
    whole: dict = field(default_factory=dict)
    connect: str = "coupling"

    def chain_key(self, key: str) -> str:
        """The chain key path of a network key path (``component[3].c`` ->
        ``coupling[1].c``); other keys (``inputs.x``, ``scenario.clutch``) as they are."""
        if key == "network" or key.startswith("network."):
            return self.connect
        m = re.match(r"(component\[\d+\])(.*)", key)
        if not m:
            return key
        head, rest = m.groups()
        if head in self.whole:
            return self.whole[head]
        if head in self.tables:
            return self.tables[head] + rest
        return key


def rewrite(data: dict) -> Rewrite:
    """The network document of the chain document ``data`` (checked table by table
    already): each inertia an ``inertia`` and its ``load`` a ``torque`` source on it; each
    coupling k its component between inertia k (flange a) and k+1 (flange b), a coupling's
    own ``ratio`` ≠ 1 an ``ideal_gear`` on its input side; a brake a ``brake`` on its
    ``node``; the engine ``engine_torque`` on its ``node``; the vehicle ``vehicle`` on the
    last inertia; each thermal node a ``thermal_node``.
    """
    comps: list = []
    conns: list = []
    tables: dict = {}
    whole: dict = {}

    def add(table: dict, *, at: str | None = None, only: str | None = None) -> None:
        key = f"component[{len(comps)}]"
        if at is not None:
            tables[key] = at
        if only is not None:
            whole[key] = only
        comps.append(table)

    inertias = data.get("inertia", [])
    names = [str(t.get("name")) for t in inertias]
    for i, t in enumerate(inertias):
        name = names[i]
        add({"type": "inertia", **{k: v for k, v in t.items() if k != "load"}},
            at=f"inertia[{i}]")
        if t.get("load"):
            add({"type": "torque", "name": f"{name}_load", "input": t["load"]},
                only=f"inertia[{i}].load")
            conns.append([f"{name}_load.flange", f"{name}.a"])
    for k, t in enumerate(data.get("coupling", [])):
        a, b = f"{names[k]}.b", f"{names[k + 1]}.a"      # one coupling fewer than inertias
        ctype = t.get("type")
        body = {key: v for key, v in t.items() if key != "type"}
        name = str(t.get("name"))
        if ctype not in _GEARS:
            ratio = body.pop("ratio", 1.0)
            if ratio != 1.0:
                gear = f"{name}_ratio"
                add({"type": "ideal_gear", "name": gear, "ratio": ratio},
                    only=f"coupling[{k}].ratio")
                conns.append([a, f"{gear}.a"])
                a = f"{gear}.b"
        add({"type": COUPLING_TYPES.get(ctype, ctype), **body}, at=f"coupling[{k}]")
        conns += [[a, f"{name}.a"], [f"{name}.b", b]]
    for i, t in enumerate(data.get("brake", [])):
        node = t.get("node")
        add({"type": "brake", **{k: v for k, v in t.items() if k != "node"}},
            at=f"brake[{i}]")
        conns.append([f"{t.get('name')}.flange", f"{node}.a"])
    for table in ("engine", "vehicle"):
        if table not in data:
            continue
        t = data[table]
        name = _NAMES[table]
        node = t.get("node") if table == "engine" else names[-1]
        add({"type": table, "name": name, **{k: v for k, v in t.items() if k != "node"}},
            at=table)
        conns.append([f"{name}.flange", f"{node}.a"])
    for i, t in enumerate(data.get("thermal", [])):
        add({"type": "thermal_node", **t}, at=f"thermal[{i}]")
    out = {k: v for k, v in data.items() if k not in CHAIN_TABLES}
    out["component"] = comps
    out["network"] = {"connect": conns}
    return Rewrite(out, tables, whole, "coupling" if data.get("coupling") else "inertia")
