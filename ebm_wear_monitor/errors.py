"""Errors that mean "bad input": the CLIs turn them into one line on stderr and exit code 2."""


class InputError(ValueError):
    """Bad user input (file, parameter, bag, argument) with a one-line, user-facing reason."""
