"""Every friction model's network plant, and its friction-rig plant, print as C.

A plant the C printer cannot print still runs (numba compiles it instead), but a new
topology then takes 10-40 s instead of about one, and the only sign is one log line: the
GMS model's kernels indexed a call's result and zeroed a matrix by a slice, and every
network with a GMS element fell back to numba unnoticed.  This walks the registry, so a
new model whose kernels use a construct the printer does not know fails here, with the
construct and the line named."""

import importlib.util

import pytest

from clutchsim.cgen import print_c
from clutchsim.cgen.loader import _entries
from clutchsim.friction import MODELS, make_model
from clutchsim.network import Network, codegen, compile_network
from clutchsim.network.components import Brake, Clutch, Inertia, TorqueSource
from clutchsim.rig import rig_source


@pytest.mark.parametrize("name", sorted(MODELS))
def test_plant_of_every_friction_model_prints_as_c(name, tmp_path):
    model = make_model(name)
    net = Network([Inertia("a", J=1.0, omega0=3.0), Inertia("b", J=0.5),
                   Clutch("k", model, command="u"), Brake("br", model, command="u"),
                   TorqueSource("drive", input="tau")],
                  [["a.a", "k.a", "drive.flange"], ["b.a", "k.b", "br.flange"]])
    topo = codegen.generate(compile_network(net))
    stem = name.replace("-", "_")
    for kind, source in (("plant", topo.source), ("rig", rig_source(model))):
        path = tmp_path / f"{kind}_{stem}.py"
        path.write_text(source)
        spec = importlib.util.spec_from_file_location(path.stem, path)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        program = print_c(mod, _entries(mod))
        # the model's own kernels are in the program, printed from their source
        assert f"cs_{stem}_force(" in program.source
        assert f"cs_{stem}_jacobian(" in program.source
