// Isomap (Tenenbaum, de Silva & Langford 2000) down to one dimension: k-nearest-neighbour
// graph of points in CIELAB, graph shortest paths (Dijkstra from every point), classical
// MDS (double centring, top eigenvector by power iteration). Serial and deterministic.
#pragma once
#include <cstddef>
#include <vector>

#include "colour/colour_space.h"

namespace moldtex::colour {

struct Isomap1D {
  std::vector<double> coordinate;  // one per point (MDS coordinate, in Delta E units)
  double eigenvalue = 0;           // top eigenvalue of the double-centred matrix
  double eigen_energy = 0;         // eigenvalue / trace of the double-centred matrix
  size_t component_count = 0;      // connected pieces of the k-NN graph before bridging
  size_t largest_component = 0;    // points in the largest piece
  double largest_bridge = 0;       // longest edge added to join pieces (Delta E), 0 if none
};

// points: at least 2; k in [1, points.size() - 1]. Pieces of the neighbour graph that
// do not touch are joined by their closest pair of points (a minimum spanning tree over
// the pieces), so every geodesic distance is finite. O(n^2 (k + log n)) time, n^2
// doubles of memory.
Isomap1D isomap_1d(const std::vector<Lab>& points, size_t k);

}  // namespace moldtex::colour
