"""adem.Case and adem.run: case files run as `adem run` runs them (adem/case.h, adem/run.h)."""
import collections
import ctypes
import json
import os
import signal
import threading
from ctypes import byref, c_char_p, c_int

from . import _lib
from ._errors import INTERRUPTED, raise_for
from ._lib import lib
from ._world import World

Progress = collections.namedtuple(
    "Progress", "time end_time step total_steps wall_seconds eta_seconds steps_per_second "
                "contacts particles final until")


def _set_strings(sets):
    """{"time.end": 0.3, "materials.glass.friction": 0.2} -> ["time.end=0.3", ...] (values as
    YAML: numbers as Python writes them, booleans true/false, lists in flow style)."""
    if sets is None:
        return []
    if isinstance(sets, dict):
        items = sets.items()
    else:  # ["key=value", ...]
        return [str(s) for s in sets]
    out = []
    for k, v in items:
        if isinstance(v, str):
            text = v
        elif isinstance(v, bool):
            text = "true" if v else "false"
        elif isinstance(v, (list, tuple)):
            text = json.dumps([x.item() if hasattr(x, "item") else x for x in v])
        else:
            text = repr(v.item() if hasattr(v, "item") else v)
        out.append("%s=%s" % (k, text))
    return out


def _c_strings(strings):
    arr = (c_char_p * max(1, len(strings)))()
    for i, s in enumerate(strings):
        arr[i] = s.encode()
    return arr


class Case:
    """A loaded case: its world, ready to run, and what the run writes (adem_case)."""

    def __init__(self, handle):
        self._c = ctypes.c_void_p(handle)
        self.world = World(lib.adem_case_world(self._c), _owner=self)

    def __del__(self):
        if getattr(self, "_c", None):
            lib.adem_case_free(self._c)
            self._c = ctypes.c_void_p()

    @classmethod
    def load(cls, path, set=None):
        """Reads, validates and builds a case file, with overrides applied on top as
        `adem run --set key.path=value` does: set={"time.end": 0.3} or ["time.end=0.3"].
        A bad case raises adem.InputError naming file, line and column."""
        sets = _set_strings(set)
        err = _lib.Error()
        h = ctypes.c_void_p()
        st = lib.adem_case_load_file(os.fsencode(path), _c_strings(sets), len(sets), byref(h),
                                     byref(err))
        raise_for(st, err)
        return cls(h.value)

    @classmethod
    def from_string(cls, text, name="case.yaml", base_dir=None, set=None):
        """A case from YAML text (relative mesh paths from base_dir, default the working
        folder)."""
        sets = _set_strings(set)
        err = _lib.Error()
        h = ctypes.c_void_p()
        st = lib.adem_case_load_string_at(text.encode(), name.encode(),
                                          os.fsencode(base_dir) if base_dir else None,
                                          _c_strings(sets), len(sets), byref(h), byref(err))
        raise_for(st, err)
        return cls(h.value)

    @classmethod
    def resume(cls, checkpoint, set=None):
        """The case of a checkpoint (a file, or the folder holding `checkpoint`), to continue
        bit for bit with adem.run (as `adem run --resume`); set may change time.end and the
        output intervals. The output continues in the checkpoint's folder."""
        path = os.fspath(checkpoint)
        if os.path.isdir(path):
            path = os.path.join(path, "checkpoint")
        sets = _set_strings(set)
        err = _lib.Error()
        h = ctypes.c_void_p()
        st = lib.adem_checkpoint_read_with(os.fsencode(path), _c_strings(sets), len(sets),
                                           byref(h), byref(err))
        raise_for(st, err)
        case = cls(h.value)
        case.out = os.path.dirname(path) or "."
        return case

    @property
    def name(self):
        return lib.adem_case_name(self._c).decode()

    @property
    def end_time(self):
        return lib.adem_case_end_time(self._c)

    @property
    def total_steps(self):
        return lib.adem_case_total_steps(self._c)

    @property
    def out(self):
        """The output folder (output.dir of the case, or out/<name>; adem run --out)."""
        return lib.adem_case_output_dir(self._c).decode()

    @out.setter
    def out(self, folder):
        err = _lib.Error()
        raise_for(lib.adem_case_set_output_dir(self._c, os.fsencode(folder), byref(err)), err)

    def checkpoint(self, path):
        """Writes the case's checkpoint (case text and whole state) to path, atomically."""
        err = _lib.Error()
        raise_for(lib.adem_checkpoint_write(self._c, os.fsencode(path), byref(err)), err)


def run(case, out=None, threads=0, progress=None):
    """Runs a case to its end time as `adem run` does, writing the same files into out (default
    the case's output folder): frames, timeseries.csv, checkpoints, plots.

    progress(p): called about once a second with an adem.Progress; raising in it stops the run
    after a checkpoint and the exception propagates. Ctrl-C (SIGINT) stops the run at the next
    progress check (about a second) after writing a checkpoint, then raises KeyboardInterrupt;
    continue with adem.run(adem.Case.resume(out)). A failed run raises adem.SimulationError and
    keeps what it wrote."""
    if out is not None:
        case.out = out
    stop = c_int(0)
    raised = []

    def on_progress(p_ptr, _user):
        p = p_ptr.contents
        if progress is not None and not raised:
            try:
                progress(Progress(p.time, p.end_time, p.step, p.total_steps, p.wall_seconds,
                                  p.eta_seconds, p.steps_per_second, p.contacts, p.particles,
                                  bool(p.final), p.until.decode("utf-8", "replace")))
            except BaseException as e:  # stop cleanly, re-raise after the checkpoint
                raised.append(e)
                stop.value = 1

    cb = _lib.PROGRESS_FN(on_progress)
    opt = lib.adem_default_run_options()
    opt.nthreads = int(threads)
    opt.progress = cb
    opt.stop_flag = ctypes.pointer(stop)
    # Ctrl-C: the handler runs (in Python) at the next progress call and asks the run to stop
    previous = None
    main = threading.current_thread() is threading.main_thread()
    if main:
        def on_sigint(signum, frame):
            stop.value = signum
        previous = signal.signal(signal.SIGINT, on_sigint)
    err = _lib.Error()
    try:
        st = lib.adem_run(case._c, byref(opt), byref(err))
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    if raised:
        raise raised[0]
    if st == INTERRUPTED:
        raise KeyboardInterrupt(err.message.decode(errors="replace"))
    raise_for(st, err)
    return case
