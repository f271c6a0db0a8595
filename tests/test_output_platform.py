"""The platform record of summary.json: which kernels a process compiled itself, and whether
Numba's cache holds a kernel's code for this machine."""

import json
import os
import subprocess
import sys
import textwrap
import time

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


CACHE_PROBE = textwrap.dedent("""
    import json, sys
    sys.path.insert(0, sys.argv[1])
    from cached_probe import twice
    from corneasim.output._platform import cached_for_this_machine
    before = cached_for_this_machine(twice)
    twice(1.0)
    print(json.dumps([before, cached_for_this_machine(twice)]))
""")


def test_the_cache_holds_code_for_this_machine_once_a_process_compiled_it(tmp_path):
    """Before the first compile there is none; after it, this and the next process find it; a
    process compiling for another CPU (``NUMBA_CPU_NAME``) does not count the host's code."""
    (tmp_path / "cached_probe.py").write_text(
        "from numba import njit\n\n\n@njit(cache=True)\ndef twice(x):\n    return 2.0 * x\n")

    def probe(**environment):
        run = subprocess.run([sys.executable, "-c", CACHE_PROBE, str(tmp_path)], capture_output=True, text=True,
                             check=True, env={**os.environ, **environment})
        return json.loads(run.stdout.strip().splitlines()[-1])

    assert probe() == [False, True]
    assert probe() == [True, True]
    assert probe(NUMBA_CPU_NAME="generic") == [False, True]


def test_platform_is_plain_json():
    platform = describe_platform()
    assert json.loads(json.dumps(platform)) == platform
    assert platform["logical_cpus"] >= 1 and platform["numba_threads"] >= 1


AGE_PROBE = textwrap.dedent("""
    import time
    time.sleep(0.3)
    from corneasim.output import process_age
    print(process_age())
""")


def test_process_age_counts_from_the_interpreter_start():
    """A process that sleeps 0.3 s before its first import is at least 0.3 s old (less the 10 ms
    resolution of the start time) and younger than the parent's clock says it lived."""
    started = time.perf_counter()
    run = subprocess.run([sys.executable, "-c", AGE_PROBE], capture_output=True, text=True, check=True)
    lived = time.perf_counter() - started
    age = float(run.stdout.strip().splitlines()[-1])
    assert 0.29 <= age < lived


STARTUP_PROBE = textwrap.dedent("""
    import json, time
    time.sleep(0.4)
    import corneasim
    short = ["mesh.preset=coarse", "preload.duration=1e-3", "solver.end_time=1e-3"]
    first = corneasim.run_scenario("needle", short).summary["run"]["startup_s"]
    after_first = time.perf_counter()
    time.sleep(0.4)
    second = corneasim.run_scenario("needle", short).summary["run"]["startup_s"]
    print(json.dumps([first, second, time.perf_counter() - after_first]))
""")


def test_startup_runs_from_the_process_start_or_the_previous_run():
    """``run.startup_s`` of a process's first run counts from the process's start (a 0.4 s sleep
    before the first import is in it) and ends before the process does; a second run's counts
    from the end of the first (the 0.4 s sleep between them is in it) and ends before it returns."""
    started = time.perf_counter()
    run = subprocess.run([sys.executable, "-c", STARTUP_PROBE], capture_output=True, text=True, check=True)
    lived = time.perf_counter() - started
    first, second, second_span = json.loads(run.stdout.strip().splitlines()[-1])
    assert 0.39 <= first < lived
    assert 0.4 <= second < second_span
