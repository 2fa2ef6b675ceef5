"""Exceptions: the library's adem_status and message, as Python exceptions."""
import re

OK, ERR_INPUT, ERR_RUNTIME, ERR_IO, ERR_NOMEM, INTERRUPTED = 0, 2, 3, 4, 5, 6

_WHERE = re.compile(r"^(?P<file>[^\n]*?):(?P<line>\d+):(?P<column>\d+): (?P<message>.*)$", re.S)


class Error(Exception):
    """Any failure the library reports: .status (the adem_status) and .message."""

    def __init__(self, message, status=None):
        super().__init__(message)
        self.message = message
        self.status = status


class InputError(Error, ValueError):
    """Bad input: a case file (then .file, .line, .column name where), an option, an array of
    the wrong shape, an unknown field or name. ValueError too."""

    def __init__(self, message, status=ERR_INPUT):
        super().__init__(message, status)
        m = _WHERE.match(message)
        self.file = m.group("file") if m else None
        self.line = int(m.group("line")) if m else None
        self.column = int(m.group("column")) if m else None
        self.reason = m.group("message") if m else message


class SimulationError(Error, RuntimeError):
    """The run went wrong (NaN, runaway overlap, an escaped particle): the message names the
    particle and the time; files written before are kept."""


class OutputError(Error, OSError):
    """A file could not be written."""


def raise_for(status, err):
    """Raises the exception of a non-zero adem_status with the message in err (ctypes Error)."""
    if status == OK:
        return
    msg = err.message.decode(errors="replace") if err is not None else "adem error %d" % status
    if status == ERR_INPUT:
        raise InputError(msg)
    if status == ERR_RUNTIME:
        raise SimulationError(msg, status)
    if status == ERR_IO:
        raise OutputError(msg, status)
    if status == ERR_NOMEM:
        raise MemoryError(msg)
    if status == INTERRUPTED:
        raise KeyboardInterrupt(msg)
    raise Error(msg, status)
