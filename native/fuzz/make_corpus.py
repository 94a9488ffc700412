#!/usr/bin/env python3
"""Writes the seed corpus of the C API fuzz target (native/fuzz/corpus/): a few valid
inputs in the byte format fuzz_c_api.cpp reads, so the fuzzer starts from meshes that
create, simulations that step and checkpoints that load. Run from anywhere; rerun after
changing the format."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "corpus")

u8 = lambda v: struct.pack("<B", v)
u16 = lambda v: struct.pack("<H", v)
f32 = lambda *v: struct.pack("<%df" % len(v), *v)

# Operation codes (enum Op in fuzz_c_api.cpp).
(RAY, CLOSEST, TRACE, PAINT, CREATE, STEP, ADD, ERASE, UNDO, FOOD, FIELDS, CKPT, RASTER, PARAMS, RESET,
 CONTINUOUS, BIAS, MAP, SURFACE_MAP, COLOUR_RAMP, SET_REACTION, INTRINSIC) = range(22)


def surface_map(which, pattern=(1.0, 0.0, 0.25, 0.0), scalar=1.0, mask=0b0101):
    """One map tool (0 geodesic, 1 Laplace, 2 diffusion, 3 gradient; +4: count one short)."""
    return u8(SURFACE_MAP) + u8(which) + f32(*pattern) + f32(scalar) + u8(mask)


def intrinsic(how=16, raw=0.0, target=200, points=((0, (0.2, 0.3, 0.5)), (1, (1.0, 0.0, 0.0)))):
    """Intrinsic triangulation: how bit 0 raw bound, bit 1 flips only, bit 2 bad
    struct_size, bit 4 valid points; target: area / bound^2; then the points."""
    data = u8(INTRINSIC) + u8(how) + f32(raw) + u16(target) + u8(len(points) - 1)
    for tri, bary in points:
        data += point(tri, bary)
    return data


def point(tri=0, bary=(1 / 3, 1 / 3, 1 / 3)):
    return u8(tri) + f32(*bary)


def brush(radius=0.3, strength=1.0, falloff=0.5, mode=0, channel=0, value=1.0, tri=0):
    return point(tri) + f32(radius, strength, falloff) + u8(mode) + u8(channel) + f32(value)


def quad_mesh(indexed=True, float_positions=True, float_uvs=True, uv_shift=0.0, no_uvs=False):
    """Unit quad, two triangles, UV = xy (+ shift); no_uvs: given without UVs (the UV
    bytes are still read, then dropped)."""
    flags = ((1 if indexed else 0) | (2 if float_positions else 0) | (4 if float_uvs else 0)
             | (8 if no_uvs else 0))
    data = u8(0) + u8(4) + u8(2) + u8(flags)
    data += f32(0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    data += bytes([0, 1, 2, 0, 2, 3])
    data += f32(*(c + uv_shift for c in (0, 0, 1, 0, 1, 1, 0, 1)))
    return data


def create(width=16, height=16, agents=60, species=1, shape=0, radius=0.3, model=0, seed=3):
    """seed & 0x80: the intrinsic domain."""
    return (u8(CREATE) + u8(width - 8) + u8(height - 8) + u16(agents - 1) + u8(seed) + u8(species - 1) +
            u8(shape) + point() + f32(radius) + u16(8) + u8(model))


def set_map(kind, a, b, how=1):
    return u8(MAP) + u8(kind) + f32(a, b) + u8(how)


seeds = {
    "quad_queries": quad_mesh() + u8(RAY) + f32(0.3, 0.4, 1, 0, 0, -1) + f32(float("inf")) +
                    u8(CLOSEST) + f32(0.2, 0.9, 0.5) + u8(TRACE) + point() + f32(1, 0.5, 0, 2.5) +
                    u8(PAINT) + u8(31) + u8(31) + brush() + u8(RASTER) + u8(8) + u8(8) + f32(*[0.5] * 8),
    "quad_sim": quad_mesh() + create() + u8(STEP) + u8(3) + u8(ADD) + brush() + u16(50) + u16(1) +
                u8(STEP) + u8(2) + u8(ERASE) + brush(radius=0.5) + u16(2) + u8(UNDO) + u16(2) +
                u8(CKPT) + u8(STEP) + u8(1),
    "quad_food_fields": quad_mesh() + create(species=2, shape=2) + u8(PARAMS) + u8(8) + f32(0.5) +
                        u8(2) + u8(1) + f32(1.0) + u8(FOOD) + u8(1) + f32(0.5, 0.5, 0, 1, 5) +
                        u8(FIELDS) + f32(1, 0, 0.5, 0, 0, 0, 0, 0) + u8(RESET) + u8(STEP) + u8(3),
    "quad_udim": quad_mesh(uv_shift=5.0) + create() + u8(STEP) + u8(2) + u8(PAINT) + u8(63) + u8(0) + brush(),
    "byte_mesh": u8(0) + u8(5) + u8(3) + u8(0) + bytes([0, 0, 0, 4, 0, 0, 4, 4, 0, 0, 4, 0, 2, 2, 4]) +
                 bytes([0, 1, 2, 0, 2, 3, 1, 4, 2]) + bytes(range(18)) + create(agents=50) + u8(STEP) + u8(3),
    # The continuous model under parameter maps: move rate, a sink with a spawn map, and
    # both stimuli, then steps and a checkpoint round trip.
    "quad_continuous_maps": quad_mesh() + create(agents=200, model=1) + set_map(0, 0.5, 2.0) +
                            set_map(5, 0.0, 1.0) + set_map(7, 1.0, 0.0) + set_map(8, -1.0, 2.0) +
                            set_map(9, 0.5, -0.5) + u8(STEP) + u8(3) + u8(CKPT) + u8(STEP) + u8(2),
    "quad_maps": quad_mesh() + surface_map(0) + surface_map(1) + surface_map(2, scalar=0.05) +
                 surface_map(3) + surface_map(4),
    "quad_intrinsic": quad_mesh() + intrinsic() + intrinsic(how=2) + intrinsic(how=1 | 16, raw=0.05, target=1000) +
                      intrinsic(how=0, target=1500),
    # A mesh without UVs: the texture domain refuses it, the intrinsic domain runs and
    # reads its result per vertex.
    "quad_no_uvs": quad_mesh(no_uvs=True) + create(agents=100, model=1) +
                   create(agents=100, model=1, seed=0x83) + u8(STEP) + u8(3),
    "checkpoint_intact": u8(1) + u8(0) + u8(0),
    "checkpoint_patched": u8(1) + u8(2) + u16(300) + u8(2) + bytes([0xff, 0xff, 0x7f]) +
                          u16(900) + u8(1) + bytes([0x80]) + u8(0),
    "checkpoint_truncated": u8(1) + u8(0) + u8(1) + u16(700),
}

os.makedirs(OUT, exist_ok=True)
for name, data in seeds.items():
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)
print(f"wrote {len(seeds)} seeds to {OUT}")
