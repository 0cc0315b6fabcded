"""Errors that mean "bad input": the CLIs turn them into one line on stderr and exit code 2."""


class InputError(ValueError):
    """Bad user input (file, parameter, bag, argument) with a one-line, user-facing reason."""


def exit_status(signum: int) -> int:
    """Exit status of a program stopped by signal ``signum``: 130 for SIGINT (Ctrl-C: interrupted, the
    CLI policy of interface.md section 5, as 128 + 2), 0 for SIGTERM (a service manager's normal stop)."""
    return 130 if signum == 2 else 0
