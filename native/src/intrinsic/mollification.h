// Intrinsic mollification (the idea of Gillespie, Sharp & Crane 2021, §"mollification";
// our own implementation): near-degenerate input triangles (zero area, a vertex on the
// opposite edge, float round-off) would give undefined angles and cotangents. Adding the
// same small length eps to every edge of the mesh makes every triangle inequality hold
// with a margin delta,
//     l_j + l_k - l_i >= delta   for every triangle and every corner i,
// because each such sum grows by exactly eps. The smallest such eps is
//     eps = max(0, max over triangles and corners of (delta - (l_j + l_k - l_i))),
// so a mesh whose triangles already have the margin is left exactly as it is. Adding the
// same amount everywhere (rather than fixing triangles one by one) changes no triangle's
// shape more than needed and keeps the lengths of shared edges consistent.
//
// The input mesh that the correspondence traces over is mollified the same way as the
// intrinsic triangulation, so the two describe one metric; only the map to 3D (barycentric
// weights on the input triangles) sees the difference, which is of the order of eps.
#pragma once

#include "intrinsic/intrinsic_mesh.h"

namespace moldtex::intrinsic {

// Default margin, relative to the mean edge length: well above double round-off of the
// lengths (1e-16 relative), well below any feature a simulation resolves.
constexpr double kDefaultMollifyMargin = 1e-6;

// Mean length over the edges of faces (0 for an empty mesh).
double mean_edge_length(const IntrinsicMesh& m);
// Adds eps (returned) to every edge length so that every face satisfies the triangle
// inequalities with margin delta (absolute, > 0).
double mollify(IntrinsicMesh& m, double delta);

}  // namespace moldtex::intrinsic
