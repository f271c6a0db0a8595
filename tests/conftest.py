"""The suite's schedule on pytest-xdist workers (``make test``: ``-n auto --dist loadfile``).

``--dist loadfile`` keeps each test file on one worker, so that a file's module fixtures (a
coarse run, a Dask cluster) run once. The tests named in :data:`SPREAD` are independent of
one another and of their file's fixtures and take tens of seconds each (the README's command
blocks): each is a work unit of its own, so that they run side by side on different workers
instead of adding up on one. Every other test is scheduled by its file, as ``loadfile`` does.
"""

SPREAD = ("tests/test_readme.py::test_block_runs[",)
"""Node-id prefixes of the tests scheduled one by one."""


def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` with the :data:`SPREAD` tests as work units of their own."""
    if config.getoption("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class FileScheduling(LoadFileScheduling):
        def _split_scope(self, nodeid):
            if nodeid.startswith(SPREAD):
                return nodeid
            return super()._split_scope(nodeid)

    return FileScheduling(config, log)
