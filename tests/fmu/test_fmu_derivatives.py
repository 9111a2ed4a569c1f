"""Directional derivatives of the exported FMU (FMI 2 fmi2GetDirectionalDerivative, FMI 3
fmi3GetDirectionalDerivative and fmi3GetAdjointDerivative), called through FMPy on the
default launch with model (6): the derivatives' sensitivities to the states (the plant's
exact Jacobian), to the inputs, and the outputs' sensitivities (central differences in the
FMU) match central differences of the FMU's own derivatives and outputs to 1e-6 at several
states; a state as an output has the seed itself; the adjoint is the transpose
(w . (J v) = (J^T w) . v); the model structure declares the dependencies and FMPy's
compliance checks still pass."""

import ctypes
import shutil
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from _dl_paths import EXAMPLES

from clutchsim.fmu import export_fmu

fmpy = pytest.importorskip("fmpy", reason="FMPy (the dev extra) runs the exported FMUs")
from fmpy.fmi2 import FMU2Model
from fmpy.fmi3 import FMU3Model
from fmpy.validation import validate_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="no C compiler on this machine")

#: |directional derivative - central difference| / max(|central difference|, 1)
TOL = 1e-6


class Plant:
    """An FMU instance in continuous-time mode with numpy access to states, inputs,
    derivatives and outputs, and its directional derivative."""

    def __init__(self, path, fmi):
        md = fmpy.read_model_description(str(path))
        self.md, self.fmi, self.path = md, fmi, path
        cls = FMU2Model if fmi == "2" else FMU3Model
        token = md.guid if fmi == "2" else md.instantiationToken
        self.fmu = cls(guid=token, unzipDirectory=fmpy.extract(str(path)),
                       modelIdentifier=md.modelExchange.modelIdentifier, instanceName="dd")
        self.fmu.instantiate()
        if fmi == "2":
            self.fmu.setupExperiment(startTime=0.0)
            self.fmu.enterInitializationMode()
            self.fmu.exitInitializationMode()
            self.fmu.newDiscreteStates()
        else:
            self.fmu.enterInitializationMode(startTime=0.0)
            self.fmu.exitInitializationMode()
            self.fmu.updateDiscreteStates()
        self.fmu.enterContinuousTimeMode()
        by = {v.name: v for v in md.modelVariables}
        self.states = [v for v in md.modelVariables if v.causality == "output"
                       and v.valueReference < len(md.derivatives)]
        self.nx = len(self.states)
        self.x_vr = [v.valueReference for v in self.states]
        self.dx_vr = [by[f"der({v.name})"].valueReference for v in self.states]
        self.u_vr = [v.valueReference for v in md.modelVariables if v.causality == "input"]
        self.y_vr = [v.valueReference for v in md.modelVariables if v.causality == "output"
                     and v.valueReference >= 2 * self.nx]
        self.x0 = np.array([float(v.start) for v in self.states])

    def get(self, vrs):
        return np.array(self.fmu.getReal(vrs) if self.fmi == "2" else self.fmu.getFloat64(vrs))

    def set_point(self, x, u):
        arr = (ctypes.c_double * self.nx)(*x)
        self.fmu.setContinuousStates(arr, self.nx)
        if self.fmi == "2":
            self.fmu.setReal(self.u_vr, list(u))
        else:
            self.fmu.setFloat64(self.u_vr, list(u))

    def dd(self, unknowns, knowns, seed):
        return np.array(self.fmu.getDirectionalDerivative(unknowns, knowns, list(seed)))


@pytest.fixture(scope="module", params=["2", "3"])
def plant(request, tmp_path_factory):
    path = tmp_path_factory.mktemp(f"dd{request.param}") / "launch.fmu"
    export_fmu(EXAMPLES / "launch.toml", path, "mykhailevych2020", fmi=request.param)
    assert validate_fmu(str(path)) == []
    p = Plant(path, request.param)
    yield p
    p.fmu.terminate()
    p.fmu.freeInstance()


def points(p, k=5):
    """Several states around the launch's start (the clutch slipping and close to lock),
    with the inputs half-way."""
    rng = np.random.default_rng(3)
    for _ in range(k):
        x = p.x0 * (1.0 + 0.1 * rng.standard_normal(p.nx)) + 0.05 * rng.standard_normal(p.nx)
        yield x, rng.uniform(0.2, 0.8, len(p.u_vr))


def central(f, x, v):
    """Second-order central difference of f along v, step 1e-6 of the moved values (the
    FMU's own, for what it differences, is fourth-order with 1e-5: an independent
    formula)."""
    nz = v != 0
    s = 1e-6 * float(np.min((1.0 + np.abs(x[nz])) / np.abs(v[nz])))
    return (f(x + s * v) - f(x - s * v)) / (2.0 * s)


def rel(a, b):
    return float(np.max(np.abs(a - b)) / max(float(np.max(np.abs(b))), 1.0))


def test_model_structure_declares_the_derivatives(plant):
    md = plant.md
    with zipfile.ZipFile(plant.path) as zf:      # FMPy 0.3.32 reads FMI 2's attribute only
        me = ET.fromstring(zf.read("modelDescription.xml")).find("ModelExchange").attrib
    if plant.fmi == "2":
        assert me["providesDirectionalDerivative"] == "true"
    else:
        assert me["providesDirectionalDerivatives"] == me["providesAdjointDerivatives"] == "true"
    knowns = {v.name for v in plant.states} | {v.name for v in md.modelVariables
                                                if v.causality == "input"}
    if plant.fmi == "3":        # FMI 3 declares the time, a known as well
        knowns.add("time")
    for d in md.derivatives:
        assert {v.name for v in d.dependencies} == knowns
        assert set(d.dependenciesKind) == {"dependent"}
    for o in md.outputs:
        if o.variable in plant.states:      # a state as output: itself, factor 1
            assert [v.name for v in o.dependencies] == [o.variable.name]
            assert o.dependenciesKind == ["constant"]
        else:
            assert {v.name for v in o.dependencies} == knowns


def test_directional_derivative_matches_differences_of_the_derivatives(plant):
    p = plant
    rng = np.random.default_rng(11)
    for x, u in points(p):
        p.set_point(x, u)

        def f(xx, u=u):
            p.set_point(xx, u)
            return p.get(p.dx_vr)
        # the exact Jacobian: column by column and along a random direction
        J = np.column_stack([p.dd(p.dx_vr, [p.x_vr[j]], [1.0]) for j in range(p.nx)])
        for j in range(p.nx):
            e = np.zeros(p.nx)
            e[j] = 1.0
            assert rel(J[:, j], central(f, x, e)) <= TOL, (p.states[j].name, x)
        v = rng.standard_normal(p.nx)
        p.set_point(x, u)
        Jv = p.dd(p.dx_vr, p.x_vr, v)
        assert np.allclose(Jv, J @ v, rtol=1e-12, atol=1e-9 * np.max(np.abs(J @ v)))
        assert rel(Jv, central(f, x, v)) <= TOL
        # a state as an output: the seed itself
        assert np.array_equal(p.dd(p.x_vr, p.x_vr, v), v)


def test_directional_derivative_to_inputs_and_of_outputs(plant):
    p = plant
    rng = np.random.default_rng(5)
    for x, u in points(p, 3):
        def g(uu, x=x):
            p.set_point(x, uu)
            return p.get(p.dx_vr)

        du = rng.standard_normal(len(u))
        p.set_point(x, u)
        assert rel(p.dd(p.dx_vr, p.u_vr, du), central(g, u, du)) <= TOL

        def h(xx, u=u):
            p.set_point(xx, u)
            return p.get(p.y_vr)
        v = rng.standard_normal(p.nx)
        p.set_point(x, u)
        assert rel(p.dd(p.y_vr, p.x_vr, v), central(h, x, v)) <= TOL
        if p.fmi == "3":        # the time, FMI 3's independent variable, is a known too

            def k(tt, u=u, x=x):
                p.fmu.setTime(float(tt[0]))
                p.set_point(x, u)
                return p.get(p.dx_vr + p.y_vr)
            vr_t = next(v.valueReference for v in p.md.modelVariables if v.name == "time")
            p.fmu.setTime(0.7)
            p.set_point(x, u)
            assert rel(p.dd(p.dx_vr + p.y_vr, [vr_t], [1.0]),
                       central(k, np.array([0.7]), np.array([1.0]))) <= TOL
            p.fmu.setTime(0.0)


def test_adjoint_derivative_is_the_transpose(plant):
    p = plant
    if p.fmi == "2":
        pytest.skip("FMI 2 has no adjoint derivatives")
    rng = np.random.default_rng(9)
    unknowns, knowns = p.dx_vr + p.y_vr, p.x_vr + p.u_vr
    for x, u in points(p, 3):
        p.set_point(x, u)
        v, w = rng.standard_normal(len(knowns)), rng.standard_normal(len(unknowns))
        Jv = p.dd(unknowns, knowns, v)
        JTw = np.array(p.fmu.getAdjointDerivative(unknowns, knowns, list(w),
                                                  nSensitivity=len(knowns)))
        assert len(JTw) == len(knowns)
        lhs, r = float(w @ Jv), float(JTw @ v)
        assert abs(lhs - r) <= 1e-8 * max(abs(lhs), float(np.abs(w).sum() * np.abs(Jv).max()))
