"""The notice that a slow first call is numba compiling, not a hang."""

import logging
import threading
import time

from clutchsim.core.compile_notice import compile_notice


def _notices(caplog):
    return [r for r in caplog.records if "compiling the integrator" in r.getMessage()]


def test_a_slow_first_call_is_announced_once(caplog):
    caplog.set_level(logging.INFO, logger="clutchsim")
    key = object()
    with compile_notice(key, "probe plant", after=0.05):
        time.sleep(0.5)
    assert len(_notices(caplog)) == 1
    msg = _notices(caplog)[0].getMessage()
    assert msg.startswith("probe plant: compiling the integrator") and "cached" in msg
    with compile_notice(key, "probe plant", after=0.05):   # second call: silent
        time.sleep(0.3)
    assert len(_notices(caplog)) == 1


def test_a_fast_first_call_says_nothing(caplog):
    caplog.set_level(logging.INFO, logger="clutchsim")
    with compile_notice(object(), "probe plant", after=0.2):
        pass
    time.sleep(0.4)                     # the cancelled timer must not fire later
    assert _notices(caplog) == []


def test_threads_sharing_a_first_call_get_one_notice(caplog):
    caplog.set_level(logging.INFO, logger="clutchsim")
    key = object()

    def run():
        with compile_notice(key, "probe plant", after=0.05):
            time.sleep(0.4)

    threads = [threading.Thread(target=run) for _ in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert len(_notices(caplog)) == 1


def test_the_launch_metrics_kernel_s_first_compilation_is_announced(monkeypatch):
    """A single run in the C engine compiles nothing that takes long but the launch
    metrics' kernel (~25 s from an empty cache): that is announced as the integrator's
    compilation is, so a first `clutchsim run` is not taken for a hang."""
    import contextlib
    import importlib
    lm = importlib.import_module("clutchsim.analysis.launch_metrics")
    seen = []

    @contextlib.contextmanager
    def notice(key, what, after=None, subject="the integrator"):
        seen.append((what, subject))
        yield True
    monkeypatch.setattr(lm, "compile_notice", notice)
    monkeypatch.setattr(lm, "_ENTRY", None)
    assert lm._kernel_entry() is not None
    assert seen == [("launch metrics", "the launch-metrics kernel")]
