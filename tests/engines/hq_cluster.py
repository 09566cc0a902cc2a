"""Runs the variants of a batch manifest as a HyperQueue job: a local HyperQueue cluster
(PyPI `hyperqueue`: the server and two one-core workers), one task per manifest line,
each with the line in HQ_ENTRY as `hq submit --each-line MANIFEST` sets it, running
`smartmesh batch MANIFEST -o OUT`.

    python3 tests/engines/hq_cluster.py SMARTMESH MANIFEST OUT WORKDIR

Prints "submitted N" once the job is in, "done" when every task has finished.
"""
import sys

from hyperqueue import Job, LocalCluster
from hyperqueue.cluster import WorkerConfig

smartmesh, manifest, out, workdir = sys.argv[1:5]
lines = open(manifest).read().splitlines()
with LocalCluster(server_dir=workdir) as cluster:
    cluster.start_worker(WorkerConfig(cores=1))
    cluster.start_worker(WorkerConfig(cores=1))
    client = cluster.client()
    job = Job(default_workdir=workdir, max_fails=None)
    for line in lines:
        job.program([smartmesh, "batch", manifest, "-o", out], env={"HQ_ENTRY": line})
    submitted = client.submit(job)
    print(f"submitted {len(lines)}", flush=True)
    client.wait_for_jobs([submitted])
print("done", flush=True)
