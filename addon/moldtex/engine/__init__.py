# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of libmoldtex (native/include/moldtex.h, ABI 1), split by object:

  structs.py     the header's constants, status codes and structs (mirrors)
  library.py     loading the library, signatures, errors, buffers, defaults, devices
  surface.py     Surface (a mesh in the core) and Intrinsic (its triangulation)
  simulation.py  Simulation
  bake.py        Bake, DomainBuild and the names of a bake's files
  colour.py      the colour map from an image

The package never imports bpy: it only knows the C API. If the library is missing or
does not match, LOAD_ERROR holds a plain-language reason and everything else in the
add-on keeps working (the panel shows the reason); calls then raise EngineError.

Buffers crossing the boundary are array.array objects (or numpy arrays when a caller
has them): native code gets their address, and the same object is handed to Blender's
foreach_set. Never wrap a ctypes array in a memoryview (it crashed Blender 3.4).

Callers use the names here (engine.Simulation, engine.MODEL_MOMAS, ...). The library's
state (LOAD_ERROR, VERSION, LIBRARY_PATH) is read live from library.py.
"""

from . import library, structs  # noqa: F401
from .structs import *  # noqa: F401,F403
from .library import (ADDON_DIR, LIBRARY_NAME, available, default_brush,  # noqa: F401
                      default_config, default_continuous_params, default_params,
                      default_reaction_params, deposit_rate_for_u, opencl_devices,
                      status_text, u_metric, BRUSH_FIELDS, _check)
from .surface import Intrinsic, Surface  # noqa: F401
from .simulation import Simulation  # noqa: F401
from .bake import (Bake, DomainBuild, checkpoint_file_name, frame_file_name,  # noqa: F401
                   metrics_file_name)
from .colour import colour_ramp_from_pixels  # noqa: F401

_LIVE = ("LOAD_ERROR", "VERSION", "LIBRARY_PATH")


def __getattr__(name):
    # The library's state changes when it is loaded again (library._load()).
    if name in _LIVE:
        return getattr(library, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
