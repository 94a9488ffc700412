#include "colour/isomap.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

namespace moldtex::colour {
namespace {

struct Edge {
  size_t to;
  double length;
};

using Graph = std::vector<std::vector<Edge>>;

void add_edge(Graph& graph, size_t i, size_t j, double length) {
  for (const Edge& e : graph[i])
    if (e.to == j) return;
  graph[i].push_back({j, length});
  graph[j].push_back({i, length});
}

// Symmetric k-NN graph (i ~ j when either is among the other's k nearest). Ties are
// broken by index, so the graph does not depend on anything but the points.
Graph knn_graph(const std::vector<Lab>& p, size_t k) {
  const size_t n = p.size();
  Graph graph(n);
  std::vector<std::pair<double, size_t>> d(n - 1);
  for (size_t i = 0; i < n; ++i) {
    size_t m = 0;
    for (size_t j = 0; j < n; ++j)
      if (j != i) d[m++] = {delta_e_squared(p[i], p[j]), j};
    std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(k), d.end());
    for (size_t r = 0; r < k; ++r) add_edge(graph, i, d[r].second, std::sqrt(d[r].first));
  }
  return graph;
}

// Connected components: label per point; returns the count.
size_t components(const Graph& graph, std::vector<size_t>& label) {
  const size_t n = graph.size(), none = std::numeric_limits<size_t>::max();
  label.assign(n, none);
  size_t count = 0;
  std::vector<size_t> stack;
  for (size_t s = 0; s < n; ++s) {
    if (label[s] != none) continue;
    label[s] = count;
    stack.push_back(s);
    while (!stack.empty()) {
      const size_t v = stack.back();
      stack.pop_back();
      for (const Edge& e : graph[v])
        if (label[e.to] == none) {
          label[e.to] = count;
          stack.push_back(e.to);
        }
    }
    ++count;
  }
  return count;
}

// Joins the pieces: Prim's algorithm over pieces, each step adding the shortest edge
// from the joined pieces to a point outside them.
// Returns the longest edge added.
double bridge(Graph& graph, const std::vector<Lab>& p, const std::vector<size_t>& label, size_t count) {
  double longest = 0.0;
  if (count <= 1) return longest;
  const size_t n = p.size();
  std::vector<char> joined(count, 0);
  joined[label[0]] = 1;
  // best[j]: the shortest distance from a joined point to point j, and that point.
  std::vector<double> best(n, std::numeric_limits<double>::infinity());
  std::vector<size_t> from(n, 0);
  auto relax_piece = [&](size_t piece) {
    for (size_t i = 0; i < n; ++i) {
      if (label[i] != piece) continue;
      for (size_t j = 0; j < n; ++j) {
        if (joined[label[j]]) continue;
        const double d = delta_e_squared(p[i], p[j]);
        if (d < best[j]) best[j] = d, from[j] = i;
      }
    }
  };
  relax_piece(label[0]);
  for (size_t step = 1; step < count; ++step) {
    size_t j_best = n;
    for (size_t j = 0; j < n; ++j)
      if (!joined[label[j]] && (j_best == n || best[j] < best[j_best])) j_best = j;
    add_edge(graph, from[j_best], j_best, std::sqrt(best[j_best]));
    longest = std::max(longest, std::sqrt(best[j_best]));
    const size_t piece = label[j_best];
    joined[piece] = 1;
    relax_piece(piece);
  }
  return longest;
}

}  // namespace

Isomap1D isomap_1d(const std::vector<Lab>& points, size_t k) {
  const size_t n = points.size();
  Isomap1D out;
  out.coordinate.assign(n, 0.0);
  if (n < 2) return out;
  k = std::min(std::max<size_t>(k, 1), n - 1);
  Graph graph = knn_graph(points, k);
  std::vector<size_t> label;
  out.component_count = components(graph, label);
  std::vector<size_t> sizes(out.component_count, 0);
  for (size_t l : label) ++sizes[l];
  out.largest_component = *std::max_element(sizes.begin(), sizes.end());
  out.largest_bridge = bridge(graph, points, label, out.component_count);

  // Squared geodesic distances, Dijkstra from every point.
  Eigen::MatrixXd b(n, n);
  std::vector<double> dist(n);
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t s = 0; s < n; ++s) {
    std::fill(dist.begin(), dist.end(), std::numeric_limits<double>::infinity());
    dist[s] = 0.0;
    queue.push({0.0, s});
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[v]) continue;
      for (const Edge& e : graph[v]) {
        const double nd = d + e.length;
        if (nd < dist[e.to]) {
          dist[e.to] = nd;
          queue.push({nd, e.to});
        }
      }
    }
    for (size_t j = 0; j < n; ++j) b(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(s)) = dist[j] * dist[j];
  }
  // Shortest paths are symmetric up to rounding; average to make B exactly symmetric.
  b = 0.5 * (b + b.transpose()).eval();
  // Double centring: B = -1/2 J D^2 J.
  const Eigen::VectorXd row_mean = b.rowwise().mean();
  const double total_mean = row_mean.mean();
  for (Eigen::Index j = 0; j < b.cols(); ++j)
    for (Eigen::Index i = 0; i < b.rows(); ++i)
      b(i, j) = -0.5 * (b(i, j) - row_mean(i) - row_mean(j) + total_mean);
  const double trace = b.trace();

  // Power iteration for the largest algebraic eigenvalue: iterate on B - shift I, with
  // shift 0 first; if the dominant eigenvalue turns out negative, shift by it (then
  // B - shift I is positive semi-definite and its top eigenvector is B's).
  auto power = [&](double shift, double& lambda) {
    Eigen::VectorXd v(n);
    for (size_t i = 0; i < n; ++i)  // deterministic start, not orthogonal to a trend
      v(static_cast<Eigen::Index>(i)) = 1.0 + std::sin(1.0 + 0.7 * static_cast<double>(i));
    v.normalize();
    lambda = 0.0;
    for (int iteration = 0; iteration < 500; ++iteration) {
      Eigen::VectorXd w = b * v - shift * v;
      const double norm = w.norm();
      if (!(norm > 0.0)) break;
      w /= norm;
      if (w.dot(v) < 0) w = -w;  // (negative dominant eigenvalue: the sign alternates)
      const double change = (w - v).norm();
      v = w;
      if (change < 1e-10) break;
    }
    lambda = v.dot(b * v);
    return v;
  };
  double lambda = 0.0;
  Eigen::VectorXd v = power(0.0, lambda);
  if (lambda <= 0.0) {
    double dominant = lambda;
    v = power(dominant, lambda);
  }
  out.eigenvalue = std::max(lambda, 0.0);
  out.eigen_energy = trace > 0.0 ? std::min(1.0, out.eigenvalue / trace) : 1.0;
  const double scale = std::sqrt(out.eigenvalue);
  for (size_t i = 0; i < n; ++i) out.coordinate[i] = scale * v(static_cast<Eigen::Index>(i));
  return out;
}

}  // namespace moldtex::colour
