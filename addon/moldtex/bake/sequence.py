# SPDX-License-Identifier: GPL-3.0-or-later
"""Baking an object's simulation into an image sequence, and playing it back.

The core's bake worker (engine.Bake) writes the frames on its own thread into
<folder>/<prefix><frame, 4 digits>.exr|png, with <prefix>metrics.csv (frame, step,
coverage, presence) and <prefix>checkpoint.bin beside them. It runs on the object's
live simulation, rebuilt from the current settings and mesh as Reset does; while it
runs the core answers ERROR_BUSY to every other call on that simulation, so sim/session.py
refuses to step it (live.check_not_baking) and skips parameter pushes.

BakeJob is shared by the modal operator (a timer polls it), the synchronous path used
in background mode and by scripts (run_synchronously), and the command line (cli.py).
Playback (use_sequence) points the material's Moldtex Image Texture node at the files
as an image sequence, so scene frame f shows file f.
"""

import os
import re
import time

import bpy

from .. import engine
from ..sim import convert
from ..sim import session as live
from ..colour import material
from ..data.mesh_export import resolve_uv_map_name
from ..settings.enums import enum_value

# properties.BAKE_FORMAT_ITEMS identifier -> engine.IMAGE_*
FORMAT_VALUES = {
    "EXR_HALF": engine.IMAGE_EXR_HALF,
    "EXR_FLOAT": engine.IMAGE_EXR_FLOAT,
    "PNG8": engine.IMAGE_PNG8,
    "PNG16": engine.IMAGE_PNG16,
}
MAX_FRAME = 999999  # moldtex.h: 0 <= first <= last <= 999999
MAX_PREFIX = 200  # the core's limit (file names stay below the usual 255 bytes)
_POLL_SECONDS = 0.02  # how often the synchronous path looks at the progress


class BakeError(Exception):
    """A problem with the bake's settings, folder or files, worded for the user."""


def sanitize_prefix(text):
    """A file-name prefix made of letters, digits, '.', '-' and '_' only. One that
    ends in a digit gets a '_', so the frame number stays the file name's last digits
    (Blender reads a sequence's frame from them)."""
    cleaned = re.sub(r"[^A-Za-z0-9._-]", "_", text)
    if cleaned and cleaned[-1].isdigit():
        cleaned += "_"
    return cleaned


def file_prefix(obj):
    """The prefix of obj's bake files: its setting, or "<object name>_"."""
    return sanitize_prefix(obj.moldtex.bake_prefix or f"{obj.name}_")


def frame_range(obj, scene):
    settings = obj.moldtex
    if settings.bake_use_scene_range:
        return scene.frame_start, scene.frame_end
    return settings.bake_frame_start, settings.bake_frame_end


def output_directory(obj):
    """Absolute output folder of obj's bake (not created here)."""
    raw = obj.moldtex.bake_directory.strip() or "//moldtex_bake/"
    if raw.startswith("//") and not bpy.data.filepath:
        raise BakeError(
            f"The output folder '{raw}' is relative to the .blend file, which has not "
            f"been saved yet: save the file first, or choose an absolute Output Folder.")
    return os.path.normpath(bpy.path.abspath(raw))


class BakePlan:
    """What a bake writes where; made from an object's settings by plan_for()."""

    def __init__(self, object_name, directory, prefix, first_frame, last_frame,
                 steps_per_frame, format_id, resume, continuous=False):
        self.object_name = object_name
        self.directory = directory
        self.prefix = prefix
        self.first_frame = int(first_frame)
        self.last_frame = int(last_frame)
        self.steps_per_frame = int(steps_per_frame)
        self.format_id = format_id
        self.image_format = FORMAT_VALUES[format_id]
        self.resume = bool(resume)
        # The continuous model: the metrics' coverage is the mean u / U (Eq. 1 over the
        # image, which holds u / U), said so in the progress lines.
        self.continuous = bool(continuous)

    @property
    def frame_count(self):
        return self.last_frame - self.first_frame + 1

    def frame_name(self, frame):
        return engine.frame_file_name(self.prefix, frame, self.image_format)

    def frame_path(self, frame):
        return os.path.join(self.directory, self.frame_name(frame))

    @property
    def metrics_path(self):
        return os.path.join(self.directory, engine.metrics_file_name(self.prefix))

    @property
    def checkpoint_path(self):
        return os.path.join(self.directory, engine.checkpoint_file_name(self.prefix))

    def describe_files(self):
        """e.g. "Suzanne_0001.exr … Suzanne_0250.exr"."""
        if self.frame_count == 1:
            return self.frame_name(self.first_frame)
        return f"{self.frame_name(self.first_frame)} … {self.frame_name(self.last_frame)}"


def plan_for(obj, scene):
    """BakePlan of obj's current bake settings; raises BakeError if they cannot work."""
    settings = obj.moldtex
    first, last = frame_range(obj, scene)
    where = ("the scene's frame range" if settings.bake_use_scene_range
             else "the bake's Start and End")
    if first < 0 or last > MAX_FRAME:
        raise BakeError(f"Frames {first}–{last} ({where}) cannot be baked: frames must be "
                        f"between 0 and {MAX_FRAME}.")
    if first > last:
        raise BakeError(f"The start frame {first} is after the end frame {last} ({where}): "
                        f"swap them.")
    prefix = file_prefix(obj)
    if len(prefix.encode("utf-8")) > MAX_PREFIX:
        raise BakeError(f"The File Prefix is {len(prefix)} characters long; at most "
                        f"{MAX_PREFIX} fit in a file name: shorten it.")
    return BakePlan(obj.name, output_directory(obj), prefix, first, last,
                    settings.bake_steps_per_frame, enum_value(settings, "bake_format"),
                    settings.bake_resume,
                    convert.model_of(settings) == engine.MODEL_CONTINUOUS)


def clipping_note(obj, plan):
    """Why this bake's files cannot hold what the simulation makes, or "": the
    continuous model's u / U runs above 1 (1 = the uniform steady state), which PNG
    (0..1) cuts off."""
    if (convert.model_of(obj.moldtex) != engine.MODEL_CONTINUOUS
            or plan.image_format not in (engine.IMAGE_PNG8, engine.IMAGE_PNG16)):
        return ""
    return ("PNG holds 0 to 1, but the continuous model's u / U runs above 1 on the "
            "trails: those values are cut off. Choose OpenEXR to keep them.")


def measure_text(coverage, continuous=False):
    """ "coverage 0.31" (MoMaS' Eq. 1), or for the continuous model, whose image holds
    u / U, "mean 0.97 U"."""
    return f"mean {coverage:.2f} U" if continuous else f"coverage {coverage:.2f}"


def progress_line(progress, continuous=False):
    """ "frame 12/250 (coverage 0.31)" of an engine progress dict ("(mean 0.97 U)" for
    the continuous model)."""
    total = progress["last_frame"] - progress["first_frame"] + 1
    text = f"frame {progress['frames_done']}/{total}"
    if progress["frames_done"]:
        text += f" ({measure_text(progress['coverage'], continuous)})"
    return text


def _clock(seconds):
    seconds = int(round(seconds))
    hours, rest = divmod(seconds, 3600)
    return (f"{hours}:{rest // 60:02d}:{rest % 60:02d}" if hours
            else f"{rest // 60}:{rest % 60:02d}")


def timing_text(entry, now=None):
    """ "0:12 elapsed, about 0:40 left" for a running bake (entry: live.LiveSim), from
    the frames this run baked so far (resumed ones are not counted); "" before."""
    started = getattr(entry, "bake_started", None)
    progress = entry.bake_progress or {}
    if started is None or not progress:
        return ""
    now = time.perf_counter() if now is None else now
    elapsed = max(0.0, now - started)
    text = f"{_clock(elapsed)} elapsed"
    total = progress["last_frame"] - progress["first_frame"] + 1
    baked = progress["frames_done"] - getattr(entry, "bake_resumed_frames", 0)
    left = total - progress["frames_done"]
    if baked > 0 and left > 0:
        text += f", about {_clock(elapsed / baked * left)} left"
    return text


class BakeJob:
    """One running bake of one object's simulation.

    Creating it rebuilds the object's simulation from its settings (as Reset does,
    pausing a live run) and starts the core's bake worker; poll() reads the progress
    (never blocks), cancel() asks it to stop after the current step, finish() waits,
    frees the worker and returns the final progress (raising EngineError if it failed).
    """

    def __init__(self, obj, depsgraph, plan):
        self.name = obj.name
        self.plan = plan
        self.finished = False
        entry = live.get(obj.name)
        if entry is not None and entry.baking:
            raise engine.EngineError(live.bake_running_message(entry, "Cannot bake"),
                                     engine.ERROR_BUSY)
        check_uv_map(obj)
        if entry is not None and entry.running:
            entry.stop_requested = True  # the live Start pauses on its next tick
        try:
            os.makedirs(plan.directory, exist_ok=True)
        except OSError as error:
            raise BakeError(f"Could not create the output folder {plan.directory}: "
                            f"{error.strerror or error}.") from None
        if not os.access(plan.directory, os.W_OK):
            raise BakeError(f"The output folder {plan.directory} is not writable: choose "
                            f"another Output Folder.")
        entry = live.ensure(obj, depsgraph, rebuild=True)
        if entry.vertex_colours:  # its UV map has zero area: it runs, on the vertices
            raise BakeError(needs_uv_map_message(obj.name, entry.flat_uv_map))
        material.sync_uv_map(obj, entry.uv_map)
        # Frames a resume will keep, as far as the metrics say (for the progress lines).
        self.resumed_frames = 0
        if plan.resume and os.path.isfile(plan.checkpoint_path):
            self.resumed_frames = sum(
                1 for row in read_metrics(plan.metrics_path)
                if plan.first_frame <= row["frame"] <= plan.last_frame)
        self.bake = engine.Bake(entry.sim, plan.directory, plan.first_frame,
                                plan.last_frame, plan.steps_per_frame, plan.image_format,
                                plan.prefix, resume=plan.resume)
        entry.bake = self.bake
        entry.bake_started = time.perf_counter()
        entry.bake_resumed_frames = self.resumed_frames
        entry.bake_plan = plan
        entry.bake_cancel_requested = False
        entry.bake_summary = ""
        entry.bake_progress = self.bake.progress()
        self.progress = entry.bake_progress

    def _entry(self):
        entry = live.get(self.name)
        if entry is None or entry.bake is not self.bake:
            return None  # the object was deleted or another file loaded: bake freed
        return entry

    def poll(self):
        """The current progress dict (engine.Bake.progress); cached for the panel."""
        entry = self._entry()
        if entry is None:
            raise BakeError(f"The bake of '{self.name}' stopped: the object was deleted or "
                            f"another file was loaded.")
        self.progress = self.bake.progress()
        entry.bake_progress = self.progress
        return self.progress

    @property
    def cancel_requested(self):
        entry = self._entry()
        return entry is not None and entry.bake_cancel_requested

    def cancel(self):
        if self._entry() is not None:
            self.bake.cancel()

    def finish(self):
        """Waits for the end, frees the worker and returns the final progress. Raises
        engine.EngineError if the bake failed, BakeError if it was freed under us."""
        if self.finished:
            return self.progress
        self.finished = True
        entry = self._entry()
        if entry is None:
            raise BakeError(f"The bake of '{self.name}' stopped: the object was deleted or "
                            f"another file was loaded.")
        failure = None
        try:
            self.bake.wait()
        except engine.EngineError as error:
            failure = error
        try:
            self.progress = self.bake.progress()
        finally:
            self.bake.release()
            entry.bake = None
            entry.bake_cancel_requested = False
        entry.bake_progress = self.progress
        try:
            entry.stats = entry.sim.get_stats()
        except engine.EngineError:
            pass
        entry.bake_summary = summary(self.plan, self.progress, failure)
        if failure is not None:
            done = self.progress["frames_done"]
            after = f" after {done} frame{'s' if done != 1 else ''}" if done else ""
            raise engine.EngineError(f"The bake of '{self.name}' failed{after}: {failure}",
                                     failure.status)
        return self.progress


def summary(plan, progress, failure=None):
    done, total = progress["frames_done"], plan.frame_count
    if failure is not None:
        return f"Bake failed after {done}/{total} frames: {failure}"
    state = progress["state"]
    if state == engine.BAKE_CANCELLED:
        return (f"Bake cancelled after {done}/{total} frames (turn on Resume to "
                f"continue it).")
    text = f"Baked {total} frames ({plan.describe_files()}) into {plan.directory}"
    if done and plan.continuous:
        text += f"; last frame: mean u / U {progress['coverage']:.3f}"
    elif done:
        text += (f"; last frame: coverage {100.0 * progress['coverage']:.1f} %, presence "
                 f"{100.0 * progress['presence']:.1f} %")
    return text + "."


def read_metrics(path):
    """Rows of a bake's metrics CSV as dicts (frame, step, coverage, presence); [] if
    the file is missing or unreadable."""
    rows = []
    try:
        with open(path, encoding="utf-8") as file:
            lines = file.read().splitlines()
    except OSError:
        return rows
    if not lines or lines[0].strip() != "frame,step,coverage,presence":
        return rows
    for line in lines[1:]:
        parts = line.split(",")
        if len(parts) != 4:
            continue
        try:
            rows.append({"frame": int(parts[0]), "step": int(parts[1]),
                         "coverage": float(parts[2]), "presence": float(parts[3])})
        except ValueError:
            continue
    return rows


def _print_frames(job, shown, progress, out):
    """Prints one line per frame finished since `shown` frames (frames faster than the
    polling get their numbers from the metrics CSV)."""
    done = progress["frames_done"]
    total = progress["last_frame"] - progress["first_frame"] + 1
    if done - shown > 1:
        rows = {row["frame"]: row for row in read_metrics(job.plan.metrics_path)}
        for index in range(shown + 1, done):
            row = rows.get(progress["first_frame"] + index - 1)
            if row is not None:
                print(f"Moldtex bake: frame {index}/{total} "
                      f"({measure_text(row['coverage'], job.plan.continuous)})", file=out)
    print(f"Moldtex bake: {progress_line(progress, job.plan.continuous)}", file=out)
    out.flush()


def run_synchronously(job, out=None):
    """Waits for a job while printing one line per frame to `out` (stdout by default),
    e.g. "Moldtex bake: frame 12/250 (coverage 0.31)"; Ctrl+C cancels it cleanly.
    Returns the final progress (see BakeJob.finish)."""
    import sys
    out = out or sys.stdout
    shown = job.resumed_frames  # frames_done of the last line printed
    if shown:
        print(f"Moldtex bake: resuming after frame {shown}/{job.plan.frame_count}",
              file=out)
        out.flush()
    interrupted = False
    try:
        while True:
            progress = job.poll()
            if progress["frames_done"] > shown:
                _print_frames(job, shown, progress, out)
                shown = progress["frames_done"]
            if progress["state"] != engine.BAKE_RUNNING:
                break
            time.sleep(_POLL_SECONDS)
    except KeyboardInterrupt:
        interrupted = True
        job.cancel()
    result = job.finish()
    if interrupted:
        print("Moldtex bake: interrupted (rerun with Resume to continue)", file=out)
        out.flush()
    return result


# ---- playback ---------------------------------------------------------------------------

def sequence_image_name(obj):
    return f"Moldtex {obj.name} baked"


def frames_on_disk(plan):
    """How many consecutive frames from the first exist (a cancelled bake leaves a
    prefix of the sequence)."""
    count = 0
    while count < plan.frame_count and os.path.isfile(plan.frame_path(plan.first_frame
                                                                        + count)):
        count += 1
    return count


def _image_path(obj, path):
    """The path stored in the image: relative to the .blend (portable to a render farm)
    when the output folder was given relative, else as it is."""
    if obj.moldtex.bake_directory.startswith("//") and bpy.data.filepath:
        try:
            return bpy.path.relpath(path)
        except ValueError:  # e.g. another drive on Windows
            return path
    return path


def _sequence_image(obj, first_path):
    name = sequence_image_name(obj)
    stored_path = _image_path(obj, first_path)
    image = bpy.data.images.get(name)
    if image is not None and image.library is None:
        image.source = 'FILE'
        image.filepath = stored_path
    else:
        image = bpy.data.images.load(first_path, check_existing=False)
        image.name = name
        image.filepath = stored_path
    image.source = 'SEQUENCE'
    image.colorspace_settings.name = 'Non-Color'  # the pheromone is data, not colour
    image.reload()  # a resumed or repeated bake rewrote the files
    return image


def needs_uv_map_message(name, flat_uv_map=""):
    """Why a bake cannot run on an object without a UV map (or with one of zero area,
    flat_uv_map), and what to do."""
    problem = (f"has a UV map ('{flat_uv_map}') whose UVs have no area, and a bake writes "
               f"texture frames laid out by it: unwrap it" if flat_uv_map else
               "has no UV map, and a bake writes texture frames laid out by one: add a UV map")
    return (f"Object '{name}' {problem} (UV ▸ Smart UV Project in Edit Mode). Without one, "
            f"Start shows the pattern as vertex colours (Intrinsic domain).")


def check_uv_map(obj):
    """Raises BakeError for an object without a UV map: the frames are textures."""
    if obj.type == 'MESH' and len(obj.data.uv_layers) == 0:
        raise BakeError(needs_uv_map_message(obj.name))


def use_sequence(obj, plan):
    """Makes obj's material play the baked frames: the Moldtex Image Texture node gets
    the sequence, so scene frame f shows file f. Sets the material up first if it has
    no Moldtex nodes. Returns (image, frame count). Raises BakeError if no frame is
    on disk."""
    check_uv_map(obj)
    count = frames_on_disk(plan)
    if count == 0:
        raise BakeError(
            f"No baked frames found: {plan.frame_path(plan.first_frame)} does not exist. "
            f"Bake first, or check the Output Folder, File Prefix, Format and frame range.")
    image = _sequence_image(obj, plan.frame_path(plan.first_frame))
    node = material.moldtex_node(obj, material.TEXTURE_NODE)
    if node is None:
        uv_map = live.uv_map_in_use(obj) or resolve_uv_map_name(obj, obj.moldtex.uv_map)
        material.setup_material(obj, image, uv_map)
        node = material.moldtex_node(obj, material.TEXTURE_NODE)
    node.image = image
    material.sync_display_range(obj)  # the frames hold what the live image holds
    user = node.image_user
    # Blender shows file number (f - frame_start + 1) + frame_offset at scene frame f
    # (BKE_image_user_frame_get), so this makes it f for f in first..first+count-1;
    # later frames hold the last one.
    user.frame_duration = count
    user.frame_start = plan.first_frame
    user.frame_offset = plan.first_frame - 1
    user.use_cyclic = False
    user.use_auto_refresh = True
    return image, count
