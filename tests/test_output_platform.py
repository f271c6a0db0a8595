"""The platform record of summary.json: which kernels a process compiled itself."""

import json
import subprocess
import sys
import textwrap

from corneasim.output._platform import describe_platform

PROBE = textwrap.dedent("""
    import json, sys
    sys.path.insert(0, sys.argv[1])
    from cached_probe import twice
    from corneasim.output._platform import compiled_in_process
    twice(1.0)
    print(json.dumps(compiled_in_process([twice])))
""")


def test_compiled_in_process_tells_a_compiling_run_from_a_cached_one(tmp_path):
    """The first process compiles a cache=True function and says so; the second loads it
    from the on-disk cache the first wrote and lists nothing."""
    (tmp_path / "cached_probe.py").write_text(
        "from numba import njit\n\n\n@njit(cache=True)\ndef twice(x):\n    return 2.0 * x\n")
    runs = [subprocess.run([sys.executable, "-c", PROBE, str(tmp_path)], capture_output=True, text=True,
                           check=True) for _ in range(2)]
    first, second = (json.loads(run.stdout.strip().splitlines()[-1]) for run in runs)
    assert first == ["cached_probe.twice"] and second == []


def test_platform_is_plain_json():
    platform = describe_platform()
    assert json.loads(json.dumps(platform)) == platform
    assert platform["logical_cpus"] >= 1 and platform["numba_threads"] >= 1
