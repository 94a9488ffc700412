# SPDX-License-Identifier: GPL-3.0-or-later
"""Headless Moldtex bake, for render farms and scripts.

Any Blender (3.4+):
    blender -b scene.blend -P <add-on folder>/moldtex/cli.py -- --object Rock \\
        --out /farm/rock_bake --frames 1 250 --steps-per-frame 2 --format exr-half \\
        --preset marble [--model continuous|gray-scott] [--domain intrinsic] [--resume]
Blender 4.2+ with the add-on enabled in the preferences:
    blender --command moldtex bake --blend scene.blend --object Rock --out ... (same)
Blender as a Python module (pip install bpy):
    python <add-on folder>/moldtex/cli.py --blend scene.blend --object Rock ...

Prints one progress line per frame ("Moldtex bake: frame 12/250 (coverage 0.31)"; for
the continuous model "(mean 0.97 U)", the mean u / U) and where the files are. Exit status: 0 done, 1 the bake failed or was interrupted (a
missing object, an unwritable folder, ...), 2 bad arguments. Arguments not given keep
the object's Bake settings saved in the .blend. Frames are whole files at any moment
(written as .partial and renamed), so a killed job can be rerun with --resume and
gives exactly the files of an uninterrupted bake.

This file runs as a script (-P) as well as a module of the add-on (the --command entry):
it needs nothing from the add-on until the add-on is enabled, and then finds the add-on
through its registered operator, whatever the add-on's module name is.
"""

import argparse
import importlib
import os
import sys

EXIT_OK = 0
EXIT_FAILURE = 1
EXIT_USAGE = 2

FORMATS = {"exr-half": "EXR_HALF", "exr-float": "EXR_FLOAT", "png8": "PNG8",
           "png16": "PNG16"}
MODELS = {"momas": "MOMAS", "continuous": "CONTINUOUS", "gray-scott": "GRAY_SCOTT"}
DOMAINS = {"texture": "TEXTURE", "intrinsic": "INTRINSIC"}
ADDON_DIR = os.path.dirname(os.path.abspath(__file__))


class UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # no sys.exit from inside Blender: run() returns 2
        raise UsageError(message)


def build_parser(prog):
    parser = _Parser(
        prog=prog, description="Bake a Moldtex object's growth into an image sequence.",
        epilog="Exit status: 0 done, 1 failed or interrupted, 2 bad arguments.")
    parser.add_argument("--object", required=True, metavar="NAME",
                        help="name of the mesh object to bake")
    parser.add_argument("--blend", metavar="FILE",
                        help="open this .blend first (for --command and the bpy module; "
                             "with 'blender -b FILE -P cli.py' it is already open)")
    parser.add_argument("--out", metavar="DIR",
                        help="output folder, created if needed; '//' = next to the "
                             ".blend (default: the object's Output Folder, "
                             "//moldtex_bake/)")
    parser.add_argument("--frames", nargs=2, type=int, metavar=("FIRST", "LAST"),
                        help="frame range (default: the object's bake range, normally "
                             "the scene's)")
    parser.add_argument("--steps-per-frame", type=int, metavar="N",
                        help="simulation steps between two frames")
    parser.add_argument("--format", choices=sorted(FORMATS),
                        help="file format of the frames")
    parser.add_argument("--prefix", help="file name prefix (default: '<object name>_')")
    parser.add_argument("--preset", metavar="NAME",
                        help="apply a look first: a shipped preset (marble, wood_grain, "
                             "golden_web, lava_rivers, moss, metal_scratches; continuous: "
                             "branching_veins, coral_maze, zebra_stripes, starbursts; "
                             "Gray-Scott: reaction_spots, reaction_labyrinth, "
                             "reaction_worms), one of yours, or a preset .py file")
    parser.add_argument("--model", choices=sorted(MODELS),
                        help="behaviour model: momas, continuous (the rate-based "
                             "model with a diffusion-decay PDE and agent turnover, "
                             "layton-intrinsic-slime.md) or gray-scott (reaction-"
                             "diffusion, no agents); applied after --preset "
                             "(default: the object's, or the preset's)")
    parser.add_argument("--domain", choices=sorted(DOMAINS),
                        help="where the pheromone lives: texture (the UV layout's "
                             "texels) or intrinsic (a triangulation of the surface: no "
                             "UV seams or stretch; continuous and gray-scott models)")
    parser.add_argument("--resume", action="store_true",
                        help="continue an interrupted bake from its checkpoint")
    parser.add_argument("--save-as", metavar="FILE",
                        help="afterwards save the .blend here, with the material playing "
                             "the baked sequence (e.g. for a separate render job)")
    return parser


def _say(text, error=False):
    stream = sys.stderr if error else sys.stdout
    print(f"moldtex bake: {'error: ' if error else ''}{text}", file=stream)
    stream.flush()


def _operator_message(error):
    # bpy.ops raises RuntimeError("Error: <report>") for an operator's ERROR report.
    text = str(error).strip()
    return text[len("Error: "):] if text.startswith("Error: ") else text


def _addon_package():
    """The enabled add-on's package, enabling it from this folder if needed."""
    import bpy
    if not hasattr(bpy.types, "MOLDTEX_OT_bake"):
        import addon_utils
        parent, name = os.path.split(ADDON_DIR)
        if parent not in sys.path:
            sys.path.insert(0, parent)
        if addon_utils.enable(name, default_set=False) is None or not hasattr(
                bpy.types, "MOLDTEX_OT_bake"):
            raise RuntimeError(f"the Moldtex add-on in {ADDON_DIR} could not be enabled "
                               f"(see the messages above)")
    module_name = bpy.types.MOLDTEX_OT_bake.__module__  # "<package>.operators.simulation"
    return importlib.import_module(module_name.rsplit(".", 2)[0])


def _apply_preset(bpy, package, obj, name):
    presets = importlib.import_module(package.__name__ + ".looks.presets")
    path = presets.find(name)
    if not path:
        known = ", ".join(sorted(presets.available())) or "none"
        raise UsageError(f"there is no preset '{name}' (presets: {known})")
    view_layer = bpy.context.view_layer
    if obj.name in view_layer.objects:
        view_layer.objects.active = obj
    override = getattr(bpy.context, "temp_override", None)
    if override is not None:
        with override(object=obj, active_object=obj):
            bpy.ops.moldtex.preset_apply(filepath=path)
    else:
        bpy.ops.moldtex.preset_apply(filepath=path)
    _say(f"applied preset {os.path.basename(path)[:-3]} ({path})")


def run(argv, prog="cli.py"):
    """Runs a headless bake; returns the exit status (never raises, never exits)."""
    parser = build_parser(prog)
    try:
        args = parser.parse_args(list(argv))
    except UsageError as error:
        parser.print_usage(sys.stderr)
        _say(str(error), error=True)
        return EXIT_USAGE
    except SystemExit as done:  # --help
        return int(done.code or 0)
    if args.frames and not 0 <= args.frames[0] <= args.frames[1] <= 999999:
        _say(f"--frames {args.frames[0]} {args.frames[1]}: need 0 <= FIRST <= LAST <= "
             f"999999", error=True)
        return EXIT_USAGE
    if args.steps_per_frame is not None and not 1 <= args.steps_per_frame <= 100000:
        _say("--steps-per-frame must be between 1 and 100000", error=True)
        return EXIT_USAGE

    import bpy
    try:
        if args.blend:
            if not os.path.isfile(args.blend):
                _say(f"the file {args.blend} does not exist", error=True)
                return EXIT_FAILURE
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend))
        package = _addon_package()
        obj = bpy.data.objects.get(args.object)
        if obj is None:
            meshes = ", ".join(sorted(o.name for o in bpy.data.objects if o.type == 'MESH'))
            _say(f"there is no object named '{args.object}' in "
                 f"{bpy.data.filepath or 'this file'} (mesh objects: {meshes or 'none'})",
                 error=True)
            return EXIT_FAILURE
        if obj.type != 'MESH':
            _say(f"'{obj.name}' is a {obj.type.title()} object, not a mesh", error=True)
            return EXIT_FAILURE
        if args.preset:
            _apply_preset(bpy, package, obj, args.preset)
        settings = obj.moldtex
        if args.model:
            settings.model = MODELS[args.model]
        if args.domain:
            settings.domain = DOMAINS[args.domain]
        if args.out:
            # "//..." stays relative to the .blend (and so does the image the material
            # plays: portable between machines); anything else is made absolute.
            settings.bake_directory = (args.out if args.out.startswith("//")
                                       else os.path.abspath(args.out))
        if args.frames:
            settings.bake_use_scene_range = False
            settings.bake_frame_start, settings.bake_frame_end = args.frames
        if args.steps_per_frame is not None:
            settings.bake_steps_per_frame = args.steps_per_frame
        if args.format:
            settings.bake_format = FORMATS[args.format]
        if args.prefix is not None:
            settings.bake_prefix = args.prefix
        settings.bake_resume = bool(args.resume)

        result = bpy.ops.moldtex.bake(object_name=obj.name)
        if result != {'FINISHED'}:
            _say("the bake did not finish (cancelled or interrupted); rerun with --resume "
                 "to continue it", error=True)
            return EXIT_FAILURE
        sequence = importlib.import_module(package.__name__ + ".bake.sequence")
        plan = sequence.plan_for(obj, bpy.context.scene)
        _say(f"{plan.frame_count} frames {plan.describe_files()} in {plan.directory}")
        _say(f"metrics {plan.metrics_path}")
        if args.save_as:
            bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save_as))
            _say(f"saved {os.path.abspath(args.save_as)} (its material plays the sequence)")
        return EXIT_OK
    except UsageError as error:
        _say(str(error), error=True)
        return EXIT_USAGE
    except RuntimeError as error:  # an operator's ERROR report, a failed enable
        _say(_operator_message(error), error=True)
        return EXIT_FAILURE
    except Exception as error:  # never a traceback without an exit status
        import traceback
        traceback.print_exc()
        _say(f"unexpected {type(error).__name__}: {error}", error=True)
        return EXIT_FAILURE


def command(argv):
    """`blender --command moldtex bake ...` (bpy.utils.register_cli_command, 4.2+)."""
    argv = list(argv)
    usage = "usage: blender --command moldtex bake --object NAME [options] (see --help)"
    if not argv or argv[0] in {"-h", "--help", "help"}:
        print(usage)
        if argv:
            build_parser("blender --command moldtex bake").print_help()
        return EXIT_OK if argv else EXIT_USAGE
    if argv[0] != "bake":
        print(usage, file=sys.stderr)
        _say(f"unknown command '{argv[0]}' (the only one is 'bake')", error=True)
        return EXIT_USAGE
    return run(argv[1:], prog="blender --command moldtex bake")


def _script_argv():
    if "--" in sys.argv:
        return sys.argv[sys.argv.index("--") + 1:]
    import bpy
    if not bpy.app.binary_path:  # python cli.py ... with the bpy module
        return sys.argv[1:]
    return []


if __name__ == "__main__":
    if sys.path and os.path.abspath(sys.path[0] or os.curdir) == ADDON_DIR:
        del sys.path[0]  # `python cli.py` put the add-on folder first: its modules'
        # names (ui, properties, ...) must not shadow others
    import bpy
    status = run(_script_argv(), prog="blender -b FILE.blend -P cli.py --")
    sys.stdout.flush()
    sys.stderr.flush()
    if not bpy.app.binary_path:
        # The bpy module: skip its crash-prone teardown (see blender_tests/run_all.py).
        os._exit(status)
    if status != EXIT_OK:
        sys.exit(status)  # Blender exits with this status (no --python-exit-code needed)
