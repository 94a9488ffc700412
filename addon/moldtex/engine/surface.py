# SPDX-License-Identifier: GPL-3.0-or-later
"""A mesh handed to the core (Surface: metric, tracing, rasterizing, rays, the map
tools' finite elements) and its intrinsic triangulation (Intrinsic)."""

import array
import ctypes

from . import library
from .library import (Handle, _Intrinsic, _Surface, _brush, _buffer_address, _check, _decode, _float_ptr,
                      _require, _struct_to_dict, _uint_ptr)
from .structs import *  # noqa: F401,F403  (the header's constants and structs)


class Surface(Handle):
    """A triangle mesh with a UV layout (moldtex_surface)."""
    _release = "moldtex_surface_release"
    _what = "surface"

    def __init__(self, positions, triangles, uvs, triangle_uvs=None):
        """positions: array('f') of x,y,z; triangles: array('I'/'i') of vertex indices,
        3 per triangle; uvs: array('f') of u,v, or None for a mesh without UVs (it runs
        on the intrinsic domain only); triangle_uvs: array('I'/'i') of 3 uv indices per
        triangle (Blender loop indices), or None for per-corner uvs."""
        lib = _require()
        self._handle = None
        desc = MeshDesc()
        lib.moldtex_mesh_desc_init(ctypes.byref(desc))
        desc.positions, n_pos = _float_ptr(positions)
        desc.triangles, n_tri = _uint_ptr(triangles)
        if uvs is None:
            if triangle_uvs is not None:
                raise EngineError("triangle_uvs without uvs.", ERROR_INVALID_ARGUMENT)
            n_uv = 0
        else:
            desc.uvs, n_uv = _float_ptr(uvs)
        if n_pos % 3 or n_tri % 3 or n_uv % 2:
            raise EngineError("Mesh arrays have the wrong length (positions need 3 floats "
                              "a vertex, triangles 3 indices, uvs 2 floats).",
                              ERROR_INVALID_ARGUMENT)
        desc.vertex_count = n_pos // 3
        desc.triangle_count = n_tri // 3
        desc.uv_count = n_uv // 2
        if triangle_uvs is not None:
            desc.triangle_uvs, n_tuv = _uint_ptr(triangle_uvs)
            if n_tuv != n_tri:
                raise EngineError("triangle_uvs needs 3 indices per triangle.",
                                  ERROR_INVALID_ARGUMENT)
        handle = _Surface()
        # The arrays stay referenced by the caller for the duration of this call.
        _check(lib.moldtex_surface_create(ctypes.byref(desc), ctypes.byref(handle)),
               "Building the surface")
        self._handle = handle

    def info(self):
        info = SurfaceInfo()
        library._lib.moldtex_surface_info_init(ctypes.byref(info))
        _check(library._lib.moldtex_surface_get_info(self.handle, ctypes.byref(info)),
               "Reading surface info")
        return _struct_to_dict(info, SURFACE_INFO_FIELDS)

    def metric(self, triangle):
        g = (ctypes.c_float * 4)()
        _check(library._lib.moldtex_surface_get_metric(self.handle, triangle, g), "Reading metric")
        return tuple(g)

    def evaluate(self, triangle, bary):
        point = SurfacePoint(triangle, (ctypes.c_float * 3)(*bary))
        position = (ctypes.c_float * 3)()
        uv = (ctypes.c_float * 2)()
        _check(library._lib.moldtex_surface_evaluate(self.handle, ctypes.byref(point), position, uv),
               "Evaluating a surface point")
        return tuple(position), tuple(uv)

    def trace(self, triangle, bary, direction, length, path_capacity=0):
        start = SurfacePoint(triangle, (ctypes.c_float * 3)(*bary))
        end = SurfacePoint()
        path = (ctypes.c_float * (3 * path_capacity))() if path_capacity else None
        count = ctypes.c_uint32(0)
        _check(library._lib.moldtex_surface_trace(self.handle, ctypes.byref(start),
                                          (ctypes.c_float * 3)(*direction), length,
                                          ctypes.byref(end), path, path_capacity,
                                          ctypes.byref(count)),
               "Tracing a path")
        points = []
        if path is not None:
            n = min(count.value, path_capacity)
            points = [tuple(path[3 * i:3 * i + 3]) for i in range(n)]
        return (end.triangle, tuple(end.bary)), points, count.value

    def rasterize_corners(self, width, height, corner_rgba):
        """Bakes per-corner values into a width × height RGBA float image over the UV
        layout (Blender's pixel order, the layout a simulation of that size uses):
        corner_rgba holds 4 floats for each corner of each triangle (array('f') or numpy
        float32 of triangle_count*12, corners in the order of `triangles`). Island texels
        interpolate their triangle's corners, gutter texels copy the texel across the
        seam, the rest is 0. Returns a new array('f') of width*height*4 floats."""
        address, count = _buffer_address(corner_rgba, ("f",), writable=False)
        width, height = int(width), int(height)
        # Sizes the core refuses get no buffer (so no 4 GiB allocation before the refusal).
        fits = 8 <= width <= 16384 and 8 <= height <= 16384
        out = array.array("f", bytes(4 * 4 * width * height if fits else 4))
        out_address, out_count = _buffer_address(out, ("f",), writable=True)
        _check(library._lib.moldtex_surface_rasterize_corners(self.handle, width, height,
                                                      ctypes.c_void_p(address), count,
                                                      ctypes.c_void_p(out_address),
                                                      out_count),
               "Rasterizing corner values")
        return out

    def ray_cast(self, origin, direction, max_distance=float("inf")):
        """Nearest hit of origin + s * direction (0 <= s <= max_distance, both faces):
        None on a miss, else a dict with triangle, bary, distance (s), position, uv and
        normal (unit, by winding). The first call builds the surface's BVH."""
        hit = RayHit()
        library._lib.moldtex_ray_hit_init(ctypes.byref(hit))
        _check(library._lib.moldtex_surface_ray_cast(self.handle, (ctypes.c_float * 3)(*origin),
                                             (ctypes.c_float * 3)(*direction),
                                             float(max_distance), ctypes.byref(hit)),
               "Casting a ray")
        if not hit.hit:
            return None
        return {"triangle": hit.point.triangle, "bary": tuple(hit.point.bary),
                "distance": hit.distance, "position": tuple(hit.position),
                "uv": tuple(hit.uv), "normal": tuple(hit.normal)}

    def closest_point(self, position):
        """Nearest surface point to a 3D position: (triangle, (b0, b1, b2), distance)."""
        point = SurfacePoint()
        distance = ctypes.c_float(0.0)
        _check(library._lib.moldtex_surface_closest_point(self.handle, (ctypes.c_float * 3)(*position),
                                                  ctypes.byref(point), ctypes.byref(distance)),
               "Finding the closest point")
        return point.triangle, tuple(point.bary), distance.value

    def paint(self, width, height, rgba, brush):
        """One brush dab into an RGBA float image of width x height over the UV layout
        (array('f') or numpy float32, >= width*height*4 floats, Blender's pixel order),
        changed in place. brush: dict of BRUSH_FIELDS (see default_brush). Returns the
        number of texels that changed."""
        b = _brush(brush)
        address, count = _buffer_address(rgba, ("f",), writable=True)
        changed = ctypes.c_uint32(0)
        _check(library._lib.moldtex_surface_paint(self.handle, int(width), int(height),
                                          ctypes.c_void_p(address), count, ctypes.byref(b),
                                          ctypes.byref(changed)),
               "Painting")
        return changed.value

    # ---- surface map tools (Layton et al. §6): per-vertex maps over the FE mesh ----

    def _vertex_map_call(self, values, extra_count):
        """(input address, input count, output array('f'), output address, count)."""
        address, count = _buffer_address(values, ("f",), writable=False)
        out = array.array("f", bytes(4 * max(count, extra_count, 1)))
        out_address, out_count = _buffer_address(out, ("f",), writable=True)
        return address, count, out, out_address, out_count

    def geodesic_distance(self, source_weights, time_factor=1.0):
        """Heat-method geodesic distance (mesh units) from the vertices whose weight is
        > 0.5 (source_weights: array('f')/numpy float32, one per vertex). Returns
        array('f') per vertex: 0 at the sources, -1 where no source is reachable."""
        address, count, out, out_address, out_count = self._vertex_map_call(source_weights, 0)
        _check(library._lib.moldtex_surface_geodesic_distance(self.handle, ctypes.c_void_p(address),
                                                      count, float(time_factor),
                                                      ctypes.c_void_p(out_address), out_count),
               "Measuring geodesic distance")
        return out

    def laplace_interpolate(self, values, fixed):
        """Harmonic blend: values where fixed (array('B')/numpy uint8, one per vertex,
        nonzero = fixed) is set, Laplacian 0 elsewhere. Returns array('f') per vertex."""
        address, count, out, out_address, out_count = self._vertex_map_call(values, 0)
        fixed_address, fixed_count = _buffer_address(fixed, ("B",), writable=False)
        if fixed_count != count:
            raise EngineError(f"The fixed mask needs one entry per value ({count}), got "
                              f"{fixed_count}.", ERROR_INVALID_ARGUMENT)
        _check(library._lib.moldtex_surface_laplace_interpolate(self.handle, ctypes.c_void_p(address),
                                                        ctypes.c_void_p(fixed_address), count,
                                                        ctypes.c_void_p(out_address), out_count),
               "Laplace interpolation")
        return out

    def diffuse_map(self, values, time):
        """Short-time diffusion (M + time L) x = M values, time in mesh units² (a blur of
        radius r, the Gaussian's standard deviation, is time = r² / 2). array('f')."""
        address, count, out, out_address, out_count = self._vertex_map_call(values, 0)
        _check(library._lib.moldtex_surface_diffuse_map(self.handle, ctypes.c_void_p(address), count,
                                                float(time), ctypes.c_void_p(out_address),
                                                out_count),
               "Diffusing a map")
        return out

    def map_gradient(self, values):
        """Per-triangle gradient of the per-vertex map: array('f') of triangle_count * 3
        (set_bias' layout)."""
        triangles = self.info()["triangle_count"]
        address, count, out, out_address, out_count = self._vertex_map_call(values, 3 * triangles)
        del out[3 * triangles:]
        out_address, out_count = _buffer_address(out, ("f",), writable=True)
        _check(library._lib.moldtex_surface_map_gradient(self.handle, ctypes.c_void_p(address), count,
                                                 ctypes.c_void_p(out_address), out_count),
               "Taking a map's gradient")
        return out


def _points_array(points, what):
    """A ctypes array of SurfacePoint from (triangle, (b0, b1, b2)) pairs."""
    points = list(points)
    if not points:
        raise EngineError(f"{what}: pass at least one point.", ERROR_INVALID_ARGUMENT)
    if len(points) > MAX_INTRINSIC_POINTS:
        raise EngineError(f"{what}: at most {MAX_INTRINSIC_POINTS} points per call, got "
                          f"{len(points)}.", ERROR_TOO_LARGE)
    array_type = SurfacePoint * len(points)
    out = array_type()
    for i, (triangle, bary) in enumerate(points):
        if len(bary) != 3:
            raise EngineError(f"{what}: point {i} needs 3 barycentric weights.",
                              ERROR_INVALID_ARGUMENT)
        out[i].triangle = int(triangle)
        out[i].bary[:] = [float(b) for b in bary]
    return out


def _points_list(points):
    return [(p.triangle, tuple(p.bary)) for p in points]


class Intrinsic(Handle):
    """Intrinsic Delaunay triangulation of a surface (moldtex_intrinsic, issue 11).

    max_circumradius: bound on the triangles' circumradius in mesh units (0: only
    Delaunay edge flips, no refinement); max_insertions: cap on inserted vertices.
    Points are (triangle, (b0, b1, b2)) pairs: triangles of the surface for input
    points, of the intrinsic triangulation for intrinsic ones. Keeps the surface alive."""
    _release = "moldtex_intrinsic_release"
    _what = "intrinsic triangulation"

    def __init__(self, surface, max_circumradius=0.0, max_insertions=None):
        lib = _require()
        self._handle = None
        params = IntrinsicParams()
        lib.moldtex_intrinsic_params_init(ctypes.byref(params))
        params.max_circumradius = float(max_circumradius)
        if max_insertions is not None:
            params.max_insertions = int(max_insertions)
        handle = _Intrinsic()
        _check(lib.moldtex_intrinsic_create(surface.handle, ctypes.byref(params),
                                            ctypes.byref(handle)),
               "Building the intrinsic triangulation")
        self._handle = handle

    def info(self):
        info = IntrinsicInfo()
        library._lib.moldtex_intrinsic_info_init(ctypes.byref(info))
        _check(library._lib.moldtex_intrinsic_get_info(self.handle, ctypes.byref(info)),
               "Reading the intrinsic triangulation's info")
        result = _struct_to_dict(info, INTRINSIC_INFO_FIELDS)
        result["message"] = _decode(info.message)
        return result

    def locate(self, points):
        """Input surface points -> intrinsic points."""
        src = _points_array(points, "Locating points")
        out = (SurfacePoint * len(src))()
        _check(library._lib.moldtex_intrinsic_locate(self.handle, src, len(src), out),
               "Locating points on the intrinsic triangulation")
        return _points_list(out)

    def to_input(self, points):
        """Intrinsic points -> input surface points."""
        src = _points_array(points, "Mapping intrinsic points")
        out = (SurfacePoint * len(src))()
        _check(library._lib.moldtex_intrinsic_to_input(self.handle, src, len(src), out),
               "Mapping intrinsic points to the surface")
        return _points_list(out)

    def vertex_points(self):
        """Each intrinsic vertex's point on the input surface (triangle
        INTRINSIC_NO_TRIANGLE for an input vertex that no triangle uses)."""
        count = self.info()["vertex_count"]
        out = (SurfacePoint * count)()
        _check(library._lib.moldtex_intrinsic_vertex_points(self.handle, out, count),
               "Reading the intrinsic vertices' points")
        return _points_list(out)
