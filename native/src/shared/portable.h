/* portable.h — the dialect shared by the C++ core and the OpenCL kernels.
 *
 * Files in shared/ are compiled twice: as C++ (the CPU backend) and as OpenCL C 1.2
 * (embedded into the OpenCL backend's program). They use only what both languages
 * have: plain structs, fixed-size integer typedefs, float math, and these macros. This
 * keeps one source of truth for the geometry, the agent rules and the constants. */
#ifndef MOLDTEX_SHARED_PORTABLE_H
#define MOLDTEX_SHARED_PORTABLE_H

#ifdef __OPENCL_C_VERSION__
typedef uchar mtx_u8;
typedef uint mtx_u32;
typedef int mtx_i32;
typedef ulong mtx_u64;
typedef long mtx_i64;
#define MTX_GLOBAL __global
#define MTX_FN static inline
#define MTX_TABLES mtx_surface_tables
#define MTX_CAST(type, value) ((type)(value))
/* Every writer stores the same value 1, so plain byte stores are enough. */
#define MTX_MARK(marks, index) ((marks)[index] = (mtx_u8)1)
/* Integer counters: exact whatever the order of the increments. */
#define MTX_COUNT(counters, index) atomic_inc((counters) + (index))
/* 32-bit integer sums (fixed-point deposits): exact whatever the order of the adds. */
#define MTX_ADD_I32(sums, index, value) atomic_add((sums) + (index), (value))
#define MTX_BEGIN_NAMESPACE
#define MTX_END_NAMESPACE
#define mtx_min(a, b) fmin((a), (b))
#define mtx_max(a, b) fmax((a), (b))
#define mtx_floor_int(v) ((int)floor(v))
#define mtx_ceil_int(v) ((int)ceil(v))
#else
#include <atomic>
#include <cmath>
#include <cstdint>
typedef uint8_t mtx_u8;
typedef uint32_t mtx_u32;
typedef int32_t mtx_i32;
typedef uint64_t mtx_u64;
typedef int64_t mtx_i64;
#define MTX_GLOBAL
#define MTX_FN inline
/* The read-only tables (mtx_surface_tables, ~25 pointers) as a parameter: by value in
 * OpenCL C, which has no references; by reference in C++, where a call the compiler does
 * not inline would copy them at every call. */
#define MTX_TABLES const mtx_surface_tables&
#define MTX_CAST(type, value) static_cast<type>(value)
#define MTX_MARK(marks, index) \
  std::atomic_ref<mtx_u8>((marks)[index]).store(1, std::memory_order_relaxed)
#define MTX_COUNT(counters, index) \
  std::atomic_ref<mtx_u32>((counters)[index]).fetch_add(1u, std::memory_order_relaxed)
#define MTX_ADD_I32(sums, index, value) \
  std::atomic_ref<mtx_i32>((sums)[index]).fetch_add((value), std::memory_order_relaxed)
#define MTX_BEGIN_NAMESPACE namespace moldtex {
#define MTX_END_NAMESPACE }
using std::ceil;
using std::cos;
using std::fabs;
using std::floor;
using std::fmax;
using std::fmin;
using std::atan2;
using std::exp;
using std::log;
using std::sin;
using std::sqrt;
/* The smaller and the larger of two floats, as fmin/fmax for numbers (the shared code
 * never passes NaN), but inlined: C++'s fmin is a libm call unless NaNs are ruled out. */
inline float mtx_min(float a, float b) { return b < a ? b : a; }
inline float mtx_max(float a, float b) { return a < b ? b : a; }
/* floor(v) and ceil(v) as an int, for |v| < 2^31 (texel coordinates): the same values as
 * (int)floor(v), from a truncation and one comparison. Without SSE4.1 (the x86-64
 * baseline) the compiler expands floor and ceil into long sequences that keep the
 * floating-point exception flags exact: they were a sixth of the instructions of a MoMaS
 * step in surface units (callgrind). */
inline int mtx_floor_int(float v) {
  const int i = static_cast<int>(v);
  return i - static_cast<int>(v < static_cast<float>(i));
}
inline int mtx_ceil_int(float v) {
  const int i = static_cast<int>(v);
  return i + static_cast<int>(v > static_cast<float>(i));
}
#endif

#endif
