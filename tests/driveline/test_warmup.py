"""The launch metrics compile in a second process only when numba's cache lacks them."""

from __future__ import annotations

import pytest

from clutchsim.scenario import warmup


class _FakeProcess:
    made: list[_FakeProcess] = []  # noqa: RUF012 (the record of one test)

    def __init__(self, target, name, daemon):
        self.target, self.name, self.daemon = target, name, daemon
        self.events: list[str] = []
        self.timeouts: list = []
        _FakeProcess.made.append(self)

    def start(self):
        self.events.append("start")

    def is_alive(self):
        return "start" in self.events

    def terminate(self):
        self.events.append("terminate")

    def join(self, timeout=None):
        self.events.append("join")
        self.timeouts.append(timeout)


class _FakeContext:
    Process = _FakeProcess


@pytest.fixture
def fake_spawn(monkeypatch):
    _FakeProcess.made = []
    monkeypatch.setattr(warmup.multiprocessing, "get_context", lambda kind: _FakeContext)
    monkeypatch.setattr(warmup.os, "cpu_count", lambda: 2)
    return _FakeProcess.made


def test_the_cache_holds_the_metrics_when_their_index_file_is_there(tmp_path, monkeypatch):
    monkeypatch.setattr(warmup, "cache_dir", str(tmp_path))
    assert not warmup._metrics_cached()
    (tmp_path / "analysis_0a1b").mkdir()
    (tmp_path / "analysis_0a1b" / "_kernels.other-12.py311.nbi").touch()
    assert not warmup._metrics_cached()
    (tmp_path / "analysis_0a1b" / "_kernels.launch_kernel-640.py311.nbi").touch()
    assert warmup._metrics_cached()
    monkeypatch.setattr(warmup, "cache_dir", "")      # no cache directory: never cached
    assert not warmup._metrics_cached()


def test_a_sweep_s_cold_cache_starts_the_child_and_stops_it_with_the_block(fake_spawn,
                                                                           monkeypatch):
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: False)
    with warmup.metrics_compiled_beside(batch=True):
        assert [p.events for p in fake_spawn] == [["start"]]
    assert fake_spawn[0].events == ["start", "terminate", "join"]
    assert fake_spawn[0].daemon and fake_spawn[0].target is warmup._compile_metrics


def test_the_child_is_stopped_when_the_block_raises(fake_spawn, monkeypatch):
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: False)
    with pytest.raises(KeyboardInterrupt), warmup.metrics_compiled_beside(batch=True):
        raise KeyboardInterrupt
    assert fake_spawn[0].events == ["start", "terminate", "join"]


def test_no_child_for_single_runs(fake_spawn, monkeypatch):
    """A single run compiles nothing but the metrics (the C engine runs the plant): a
    child would only compile them a second time, beside the parent."""
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: False)
    with warmup.metrics_compiled_beside():
        pass
    assert fake_spawn == []


def test_work_first_starts_the_child_and_waits_for_it(fake_spawn, monkeypatch):
    """The demo's drift test runs first: the kernel compiles beside it even with the C
    engine, and the launches wait for the child instead of compiling the kernel again."""
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: False)
    with warmup.metrics_compiled_beside(work_first=True) as beside:
        assert beside.started
        assert fake_spawn[0].target is warmup._compile_metrics   # the kernel only
        beside.wait()
        assert fake_spawn[0].events == ["start", "join"]
        fake_spawn[0].events.remove("start")                     # the child has ended
        beside.wait()                                            # a second wait: no join
        assert fake_spawn[0].events == ["join"]
    assert fake_spawn[0].events == ["join", "join"]              # not terminated


def test_the_first_launch_analysed_waits_for_the_child(fake_spawn, monkeypatch):
    """Within the block the kernel is not compiled a second time beside the child: the
    first analysis joins the child, then loads the kernel (here from the suite's cache)."""
    import importlib
    lm = importlib.import_module("clutchsim.analysis.launch_metrics")
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: False)
    monkeypatch.setattr(lm, "_ENTRY", None)
    with warmup.metrics_compiled_beside(work_first=True):
        assert fake_spawn[0].events == ["start"]
        assert lm._kernel_entry() is not None
        assert fake_spawn[0].events == ["start", "join"]
    assert lm._WAIT is None


def test_a_child_that_hangs_does_not_hang_the_run(fake_spawn, monkeypatch, caplog):
    """The wait is bounded: past it, this process compiles the kernel itself (said in the
    log) and the block's end stops the child."""
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: False)
    with warmup.metrics_compiled_beside(work_first=True) as beside, \
            caplog.at_level("INFO", logger="clutchsim"):
        beside.wait(timeout=2.0)          # the fake child never ends
    assert fake_spawn[0].timeouts[0] == 2.0
    assert fake_spawn[0].events == ["start", "join", "terminate", "join"]
    assert "has not compiled the kernel in 2 s; compiling it here" in caplog.text


def test_waiting_without_a_child_returns_at_once(fake_spawn, monkeypatch):
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: True)
    with warmup.metrics_compiled_beside(work_first=True) as beside:
        assert not beside.started
        beside.wait()
    assert fake_spawn == []


@pytest.mark.parametrize(("cached", "cpus"), [(True, 2), (False, 1)])
def test_no_child_with_the_metrics_cached_or_one_core(fake_spawn, monkeypatch, cached, cpus):
    monkeypatch.setattr(warmup, "_metrics_cached", lambda: cached)
    monkeypatch.setattr(warmup.os, "cpu_count", lambda: cpus)
    with warmup.metrics_compiled_beside(batch=True):
        pass
    assert fake_spawn == []


def test_the_child_swallows_a_failure(monkeypatch):
    """What the child runs never raises: a failure only costs the parent the compile."""
    import logging

    from clutchsim.analysis import launch_batch

    def broken(*args, **kwargs):
        raise RuntimeError("boom")
    monkeypatch.setattr(launch_batch, "kernel_signature_example", broken)
    logger = logging.getLogger("clutchsim")
    level = logger.level
    try:
        warmup._compile_metrics()
    finally:
        logger.setLevel(level)      # the child silences the logger: not this process's


def test_the_child_compiles_the_energy_balance_a_run_calls():
    # the child compiles energy_balance for energy_balance_signature(); a run that called
    # it with other types would compile it again, in series, after the wait
    import importlib

    from clutchsim.analysis import _kernels as _k
    from clutchsim.scenario import load_scenario, run_scenario
    lm = importlib.import_module("clutchsim.analysis.launch_metrics")  # (the package's
    # launch_metrics is the function)
    res = run_scenario(load_scenario(None)).result
    lm.energy_balance(res)
    assert lm.energy_balance_signature() in _k.energy_balance.signatures


def test_the_figures_are_drawn_before_the_first_launch_is_analysed(tmp_path, monkeypatch):
    # the figures need only the results: drawn first, they fill the time the first
    # analysis would wait for a child compiling the metrics (the demo: ~5 s)
    from clutchsim.scenario import load_scenario, outputs
    from clutchsim.scenario import run as run_mod
    order = []
    draw, analyse = outputs._run_figures, run_mod.analyse_system
    monkeypatch.setattr(outputs, "_run_figures",
                        lambda *a, **k: (order.append("figures"), draw(*a, **k))[1])
    monkeypatch.setattr(run_mod, "analyse_system",
                        lambda *a, **k: (order.append("analysis"), analyse(*a, **k))[1])
    outputs.write_runs(load_scenario(None), ["mykhailevych2020", "coulomb-robust"], tmp_path)
    assert order == ["figures", "analysis", "analysis"]
    assert {p.name for p in tmp_path.glob("*.png")} == {
        "launch_mykhailevych2020.png", "launch_coulomb-robust.png", "comparison.png"}
