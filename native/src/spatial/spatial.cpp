#include "spatial/spatial.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"

namespace moldtex {

namespace {

const char* error_name(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

[[noreturn]] void embree_fail(RTCError e, const std::string& what) {
  fail(e == RTC_ERROR_OUT_OF_MEMORY ? MOLDTEX_ERROR_OUT_OF_MEMORY : MOLDTEX_ERROR_UNAVAILABLE,
       "Embree failed while " + what + " (" + error_name(e) + ")");
}

struct D3 {
  double x, y, z;
};
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(double s, D3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Closest point of triangle (a, b, c) to p as barycentrics (Ericson, Real-Time Collision
// Detection 5.1.5), in double.
void closest_on_triangle(D3 p, D3 a, D3 b, D3 c, double bary[3]) {
  const D3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) { bary[0] = 1; bary[1] = 0; bary[2] = 0; return; }
  const D3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) { bary[0] = 0; bary[1] = 1; bary[2] = 0; return; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    bary[0] = 1 - v; bary[1] = v; bary[2] = 0;
    return;
  }
  const D3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) { bary[0] = 0; bary[1] = 0; bary[2] = 1; return; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    bary[0] = 1 - w; bary[1] = 0; bary[2] = w;
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    bary[0] = 0; bary[1] = 1 - w; bary[2] = w;
    return;
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  bary[0] = 1 - v - w; bary[1] = v; bary[2] = w;
}

void store_bary(const double in[3], float out[3]) {
  float b[3] = {static_cast<float>(in[0]), static_cast<float>(in[1]), static_cast<float>(in[2])};
  mtx_clamp_bary(b);
  for (int k = 0; k < 3; ++k) out[k] = b[k];
}

struct PointQueryState {
  const Surface* surface;
  const std::vector<uint32_t>* triangle_of_prim;
  D3 p;
  bool found = false;
  uint32_t triangle = 0;
  double bary[3] = {0, 0, 0};
  double distance2 = std::numeric_limits<double>::infinity();
};

D3 vertex(const Surface& s, uint32_t t, int c) {
  const float* v = &s.positions[3 * s.triangles[3 * t + c]];
  return {v[0], v[1], v[2]};
}

bool point_query_callback(RTCPointQueryFunctionArguments* args) {
  PointQueryState& q = *static_cast<PointQueryState*>(args->userPtr);
  const uint32_t t = (*q.triangle_of_prim)[args->primID];
  const D3 a = vertex(*q.surface, t, 0), b = vertex(*q.surface, t, 1), c = vertex(*q.surface, t, 2);
  double bary[3];
  closest_on_triangle(q.p, a, b, c, bary);
  const D3 x = bary[0] * a + bary[1] * b + bary[2] * c;
  const D3 d = x - q.p;
  const double d2 = dot(d, d);
  if (d2 < q.distance2 || (d2 == q.distance2 && t < q.triangle)) {
    q.distance2 = d2;
    q.found = true;
    q.triangle = t;
    for (int k = 0; k < 3; ++k) q.bary[k] = bary[k];
    // Shrink the search sphere (Embree may only make it smaller); a hair above the
    // exact distance so that float rounding of the bounds never culls a tie.
    const float r = static_cast<float>(std::sqrt(d2) * (1 + 1e-6)) + 1e-30f;
    if (r < args->query->radius) {
      args->query->radius = r;
      return true;
    }
  }
  return false;
}

// Embree asserts (and Debian's build aborts) on a ray whose origin or direction has a
// component of magnitude 1.844e18 or more (FLT_LARGE in its Ray::valid()), and it clamps
// direction components below 1e-18 (min_rcp_input), so shorter directions miss. Queries
// are kept inside these limits, with a margin.
constexpr double kMaxQueryCoordinate = 1e18;
constexpr double kMinDirectionLength = 1e-18;

std::string format_vector(const float v[3]) {
  char text[96];
  std::snprintf(text, sizeof(text), "(%g, %g, %g)", v[0], v[1], v[2]);
  return text;
}

bool in_query_range(const float v[3]) {
  for (int k = 0; k < 3; ++k)
    if (!(std::fabs(v[k]) <= kMaxQueryCoordinate)) return false;
  return true;
}

void require_query_point(const float p[3], const char* what) {
  if (!in_query_range(p))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         std::string(what) + " " + format_vector(p) +
             " is too far away: each coordinate must be a finite number within +-1e18 mesh "
             "units (the ray tracer cannot represent more)");
}

// Embree's (non-robust) triangle test divides by the dot product of the ray and the
// triangle's normal: for a ray (nearly) in a triangle's plane that can be a denormal, and
// the hit distance comes back NaN (found by the fuzz target). Such candidates are not
// hits: reject them here so that traversal goes on to the real nearest hit. Valid hits
// pass untouched.
void reject_undefined_hits(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    if (!(t >= 0.f && std::isfinite(t) && std::isfinite(u) && std::isfinite(v))) args->valid[i] = 0;
  }
}

}  // namespace

void validate_ray(const float origin[3], const float direction[3], float max_distance) {
  require_query_point(origin, "The ray origin");
  if (!in_query_range(direction))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The ray direction " + format_vector(direction) +
             " is too long: each component must be a finite number within +-1e18 (any length "
             "works: pass a unit vector)");
  double length2 = 0;
  for (int k = 0; k < 3; ++k) length2 += double(direction[k]) * direction[k];
  if (!(std::sqrt(length2) >= kMinDirectionLength))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The ray direction " + format_vector(direction) +
             " is zero or too short (length below 1e-18): pass a unit vector");
  if (std::isnan(max_distance) || max_distance < 0.f)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The ray's maximum distance must be >= 0 (INFINITY for no limit)");
}

void validate_query_point(const float position[3]) {
  require_query_point(position, "The query position");
}

struct SpatialIndex::Scene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<uint32_t> triangle_of_prim;  // Embree primitive -> surface triangle
  ~Scene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* what) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) embree_fail(e, what);
  }
};

SpatialIndex::SpatialIndex(std::shared_ptr<const Surface> surface) : surface_(std::move(surface)) {}
SpatialIndex::~SpatialIndex() = default;

const SpatialIndex::Scene& SpatialIndex::scene() const {
  std::call_once(built_, [this] {
    const Surface& s = *surface_;
    auto sc = std::make_unique<Scene>();
    sc->device = rtcNewDevice("verbose=0");
    if (!sc->device) embree_fail(rtcGetDeviceError(nullptr), "starting (rtcNewDevice)");
    for (uint32_t t = 0; t < s.triangle_count(); ++t)
      if (!s.degenerate[t]) sc->triangle_of_prim.push_back(t);
    const size_t prims = sc->triangle_of_prim.size();
    if (prims == 0) fail(MOLDTEX_ERROR_INVALID_MESH, "The surface has no triangle with area");
    sc->scene = rtcNewScene(sc->device);
    sc->check("creating a scene");
    rtcSetSceneBuildQuality(sc->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(sc->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    sc->check("creating the triangle geometry");
    struct Release {
      RTCGeometry g;
      ~Release() { rtcReleaseGeometry(g); }
    } release{g};
    float* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), s.vertex_count()));
    sc->check("allocating the vertex buffer");
    if (!v) embree_fail(RTC_ERROR_OUT_OF_MEMORY, "allocating the vertex buffer");
    std::copy(s.positions.begin(), s.positions.end(), v);
    unsigned* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), prims));
    sc->check("allocating the index buffer");
    if (!idx) embree_fail(RTC_ERROR_OUT_OF_MEMORY, "allocating the index buffer");
    for (size_t i = 0; i < prims; ++i)
      for (int c = 0; c < 3; ++c) idx[3 * i + c] = s.triangles[3 * sc->triangle_of_prim[i] + c];
    rtcSetGeometryIntersectFilterFunction(g, reject_undefined_hits);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(sc->scene, g, 0);
    sc->check("building the geometry");
    rtcCommitScene(sc->scene);
    sc->check("building the BVH");
    scene_ = std::move(sc);
  });
  return *scene_;
}

RayHitResult SpatialIndex::ray_cast(const float origin[3], const float direction[3],
                                    float max_distance) const {
  validate_ray(origin, direction, max_distance);
  const Scene& sc = scene();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = origin[0];
  rh.ray.org_y = origin[1];
  rh.ray.org_z = origin[2];
  rh.ray.dir_x = direction[0];
  rh.ray.dir_y = direction[1];
  rh.ray.dir_z = direction[2];
  rh.ray.tnear = 0.f;
  rh.ray.tfar = max_distance;
  rh.ray.mask = 0xffffffffu;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(sc.scene, &context, &rh);
  RayHitResult out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  if (!(rh.ray.tfar >= 0.f && rh.ray.tfar <= max_distance))
    fail(MOLDTEX_ERROR_INTERNAL, "Embree reported a hit outside the ray's range");
  if (rh.hit.primID >= sc.triangle_of_prim.size())
    fail(MOLDTEX_ERROR_INTERNAL, "Embree reported a hit on an unknown triangle");
  out.hit = true;
  out.triangle = sc.triangle_of_prim[rh.hit.primID];
  // Embree's (u, v) weigh corners 1 and 2.
  const double b[3] = {1.0 - rh.hit.u - rh.hit.v, rh.hit.u, rh.hit.v};
  store_bary(b, out.bary);
  out.distance = rh.ray.tfar;
  return out;
}

ClosestPointResult SpatialIndex::closest_point(const float position[3]) const {
  validate_query_point(position);
  const Scene& sc = scene();
  PointQueryState state;
  state.surface = surface_.get();
  state.triangle_of_prim = &sc.triangle_of_prim;
  state.p = {position[0], position[1], position[2]};
  RTCPointQuery query{};
  query.x = position[0];
  query.y = position[1];
  query.z = position[2];
  query.time = 0.f;
  query.radius = std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(sc.scene, &query, &context, point_query_callback, &state);
  if (!state.found) fail(MOLDTEX_ERROR_INTERNAL, "The closest-point query found no triangle");
  ClosestPointResult out;
  out.triangle = state.triangle;
  store_bary(state.bary, out.bary);
  out.distance = std::sqrt(state.distance2);
  return out;
}

}  // namespace moldtex
