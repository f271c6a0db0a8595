"""The suite's schedule on pytest-xdist workers (``make test``: ``-n auto --dist loadfile``).

``--dist loadfile`` keeps each test file on one worker, so that a file's module fixtures (a
coarse run, a Dask cluster) run once. The tests named in :data:`SPREAD` are independent of
one another and of their file's fixtures and take tens of seconds each (the README's command
blocks): each is a work unit of its own, so that they run side by side on different workers
instead of adding up on one. Every other test is scheduled by its file, as ``loadfile`` does.

The workers take the work units in the order of :data:`FIRST`, then in the order of
collection. A worker takes the next unit when it is done with one, so the suite ends when
its last unit does: started last, a file of half a minute would keep one worker busy while
the other idles (xdist's own order, by the number of tests, puts such files last: they have
few tests each). The list is the longest units of a run, longest first, and the files that
compile the element kernels, which the others then load from Numba's cache.
"""

SPREAD = ("tests/test_readme.py::test_block_runs[",)
"""Node-id prefixes of the tests scheduled one by one."""

FIRST = (
    "tests/test_elements.py", "tests/test_elements_fibre.py", "tests/test_study.py",
    "tests/test_readme.py::test_block_runs[bash-1]", "tests/test_scenario_trephine_compare.py",
    "tests/test_reliability_signals.py", "tests/test_scenario_needle.py",
    "tests/test_scenario_resume.py", "tests/test_shell_point_stiffness.py",
    "tests/test_output_platform.py", "tests/test_fuzz_input.py",
    "tests/test_scenario_trephine.py", "tests/test_cut_plateau.py", "tests/test_study_case.py",
)
"""Node-id prefixes of the work units taken first, in this order."""


def _rank(nodeid):
    """Position of a node id's prefix in :data:`FIRST`, or its length."""
    return next((k for k, prefix in enumerate(FIRST) if nodeid.startswith(prefix)), len(FIRST))


def pytest_collection_modifyitems(items):
    """Collection order with the units of :data:`FIRST` in front (a stable sort)."""
    items.sort(key=lambda item: _rank(item.nodeid))


def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` with the :data:`SPREAD` tests as work units of their own, taken in
    collection order."""
    if config.getoption("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    config.option.loadscopereorder = False

    class FileScheduling(LoadFileScheduling):
        def _split_scope(self, nodeid):
            if nodeid.startswith(SPREAD):
                return nodeid
            return super()._split_scope(nodeid)

    return FileScheduling(config, log)
