"""The two ways a tool of this package stops short, each one line for the user (cli.run prints it):
input that cannot be used (exit 2) and a result that cannot be written (exit 1)."""


class Unusable(Exception):
    """Input that cannot be used: a file, a value or an option. Exit 2."""


class CannotWrite(Exception):
    """A result that could not be written (a full disk, a directory that is not writable). Exit 1."""
