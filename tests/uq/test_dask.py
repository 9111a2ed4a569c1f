"""The same study on a Dask cluster (a LocalCluster started here) and in process: the same
samples, the same table, the same answers."""

from __future__ import annotations

import pytest

from clutchsim.studies.sweeps import read_results
from clutchsim.studies.uq import uq


def test_dask_runs_the_same_study_as_threads(tmp_path):
    distributed = pytest.importorskip("distributed")
    vary = {"vehicle.grade": "uniform(0,8)", "vehicle.mass": "triangular(1100,1300,1500)"}
    kw = {"method": "lhs", "samples": 12, "seed": 8, "chunk_size": 5}
    local = uq(None, vary, out=tmp_path / "threads", **kw)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        remote = uq(None, vary, out=tmp_path / "dask", backend=client, **kw)
    assert read_results(remote.path).equals(read_results(local.path))
    assert remote.probabilities == local.probabilities
    assert remote.quantiles == local.quantiles
