"""The Python side of tests/support/cli_checks.sh: a block of a tests/cli script prints one line
per check, which `checks_from` counts. Used as `from checks import check` (cli_checks.sh puts
tests/support on PYTHONPATH)."""


def check(name, ok):
    """Prints "ok: NAME" when ok is true, "FAIL: NAME" otherwise."""
    print(("ok: " if ok else "FAIL: ") + name)
