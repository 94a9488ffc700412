# SPDX-License-Identifier: GPL-3.0-or-later
"""Bakes on the core's worker thread (Bake), intrinsic domains built ahead (DomainBuild),
and the names of a bake's files."""

import ctypes
import os

from . import library
from .library import (Handle, _Bake, _DomainBuild, _check, _decode, _fill, _path_bytes, _require,
                      _struct_to_dict)
from .structs import *  # noqa: F401,F403  (the header's constants and structs)


def frame_file_name(prefix, frame, image_format):
    """The name a bake gives frame `frame`: <prefix><frame, 4 digits>.exr|png."""
    return f"{prefix}{int(frame):04d}{IMAGE_EXTENSIONS[int(image_format)]}"


def metrics_file_name(prefix):
    return f"{prefix}metrics.csv"


def checkpoint_file_name(prefix):
    return f"{prefix}checkpoint.bin"


class Bake(Handle):
    """A native bake (moldtex_bake): frames first_frame..last_frame of a simulation
    written into `directory` by the core's own thread.

    It resets the simulation; frame f is the state after (f - first_frame + 1) *
    steps_per_frame steps. Files: frame_file_name(prefix, f, format) for each frame,
    metrics_file_name(prefix) (frame, step, coverage, presence) and, with
    write_checkpoints, checkpoint_file_name(prefix) after every frame; resume=True
    continues from that checkpoint with bit-identical frames. While it runs, every other
    call on the simulation raises EngineError with status ERROR_BUSY.
    progress() never blocks; wait() blocks (without holding Python's GIL).
    """
    _release = "moldtex_bake_release"
    _what = "bake"

    def __init__(self, sim, directory, first_frame, last_frame, steps_per_frame,
                 image_format=IMAGE_EXR_HALF, file_prefix="moldtex_", resume=False,
                 write_checkpoints=True):
        lib = _require()
        self._handle = None
        desc = BakeDesc()
        lib.moldtex_bake_desc_init(ctypes.byref(desc))
        # The core copies both strings before moldtex_bake_start returns; they are kept
        # here anyway so that nothing points into freed memory.
        self._directory = _path_bytes(directory)
        self._prefix = os.fsencode(file_prefix)
        desc.directory = self._directory
        desc.file_prefix = self._prefix
        desc.first_frame = int(first_frame)
        desc.last_frame = int(last_frame)
        desc.steps_per_frame = int(steps_per_frame)
        desc.format = int(image_format)
        desc.write_checkpoints = 1 if write_checkpoints else 0
        desc.resume = 1 if resume else 0
        handle = _Bake()
        _check(lib.moldtex_bake_start(sim.handle, ctypes.byref(desc), ctypes.byref(handle)),
               "Starting the bake")
        self._handle = handle
        self.directory = os.fsdecode(self._directory)
        self.file_prefix = file_prefix
        self.first_frame = desc.first_frame
        self.last_frame = desc.last_frame
        self.steps_per_frame = desc.steps_per_frame
        self.image_format = desc.format
        self.resume = bool(resume)

    @property
    def frame_count(self):
        return self.last_frame - self.first_frame + 1

    def frame_path(self, frame):
        return os.path.join(self.directory,
                            frame_file_name(self.file_prefix, frame, self.image_format))

    def progress(self):
        """dict: state (BAKE_*), first_frame, last_frame, last_frame_written, frames_done
        (whole frames on disk, resumed ones included), step_count, coverage, presence
        (of the last frame written) and message (why it failed)."""
        p = BakeProgress()
        library._lib.moldtex_bake_progress_init(ctypes.byref(p))
        _check(library._lib.moldtex_bake_get_progress(self.handle, ctypes.byref(p)),
               "Reading the bake's progress")
        result = _struct_to_dict(p, BAKE_PROGRESS_FIELDS)
        result["message"] = _decode(p.message)
        return result

    def running(self):
        return self.progress()["state"] == BAKE_RUNNING

    def cancel(self):
        """Asks the bake to stop after the current step (no partial frame is left)."""
        if self._handle is not None:
            library._lib.moldtex_bake_cancel(self._handle)

    def wait(self):
        """Blocks until the bake ends; raises EngineError if it failed (a cancelled
        bake is not a failure: see progress()["state"])."""
        _check(library._lib.moldtex_bake_wait(self.handle), "The bake")


class DomainBuild(Handle):
    """Builds the intrinsic domain a Simulation(surface, config) would run on, on the
    core's own thread (moldtex_domain_build), so that an interface can show its progress
    and cancel it; the Simulation created next with the same surface, size and bound
    reuses it (domain_info()["from_cache"]). config as for Simulation (domain must be
    DOMAIN_INTRINSIC); thread_count as the params' (0 = all cores).
    progress() never blocks; wait() blocks (without holding Python's GIL)."""
    _release = "moldtex_domain_build_release"
    _what = "domain build"

    def __init__(self, surface, config, thread_count=0):
        lib = _require()
        self._handle = None
        c = SimConfig()
        lib.moldtex_sim_config_init(ctypes.byref(c))
        config = dict(config or {})
        config.pop("seed_center", None)   # (where agents start does not shape the domain)
        config.pop("fields_rgba", None)
        _fill(c, config, CONFIG_FIELDS, "config")
        handle = _DomainBuild()
        _check(lib.moldtex_domain_build_start(surface.handle, ctypes.byref(c),
                                              int(thread_count), ctypes.byref(handle)),
               "Building the intrinsic triangulation")
        self._handle = handle

    def progress(self):
        """dict: state (BAKE_RUNNING / _FINISHED / _CANCELLED / _FAILED), stage (BUILD_*),
        vertex_count, fraction (0..1, an estimate that only grows), seconds, from_cache
        and message (why it failed)."""
        p = DomainBuildProgress()
        library._lib.moldtex_domain_build_progress_init(ctypes.byref(p))
        _check(library._lib.moldtex_domain_build_get_progress(self.handle, ctypes.byref(p)),
               "Reading the build's progress")
        return {"state": p.state, "stage": p.stage, "vertex_count": p.vertex_count,
                "fraction": p.fraction, "seconds": p.seconds,
                "from_cache": bool(p.from_cache), "message": _decode(p.message)}

    def running(self):
        return self.progress()["state"] == BAKE_RUNNING

    def cancel(self):
        """Asks the build to stop (nothing of it is kept); returns at once."""
        if self._handle is not None:
            library._lib.moldtex_domain_build_cancel(self._handle)

    def wait(self):
        """Blocks until the build ends; raises EngineError if it failed or was cancelled
        (status ERROR_CANCELLED)."""
        _check(library._lib.moldtex_domain_build_wait(self.handle), "Building the intrinsic triangulation")
