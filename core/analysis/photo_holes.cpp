// SPDX-License-Identifier: MIT
// Photograph holes: smoothing, Otsu threshold, border-free 4-connected components, and the
// pixel-grid comparison with the simulated hole outlines.
#include "core/analysis/photo_holes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fesph {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kBins = 256;

// 3x3 binomial smoothing (1 2 1 / 2 4 2 / 1 2 1), borders clamped: pixel noise must not
// speckle the plate with tiny holes or fray the hole edges.
GrayImage smoothed(const GrayImage& in) {
  GrayImage out = in;
  const int w = in.width, h = in.height;
  const auto px = [&](int i, int j) {
    return in.at(std::clamp(i, 0, w - 1), std::clamp(j, 0, h - 1));
  };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float s = px(i - 1, j - 1) + 2 * px(i, j - 1) + px(i + 1, j - 1) +
                      2 * px(i - 1, j) + 4 * px(i, j) + 2 * px(i + 1, j) +
                      px(i - 1, j + 1) + 2 * px(i, j + 1) + px(i + 1, j + 1);
      out.value[static_cast<std::size_t>(j) * w + i] = s / 16;
    }
  return out;
}

int binOf(float v) { return std::clamp(static_cast<int>(v * kBins), 0, kBins - 1); }

}  // namespace

double otsuThreshold(const GrayImage& image) {
  std::vector<double> hist(kBins, 0);
  for (float v : image.value) hist[binOf(v)] += 1;
  const double n = static_cast<double>(image.value.size());
  double sum_all = 0;
  for (int k = 0; k < kBins; ++k) sum_all += k * hist[k];
  double w0 = 0, sum0 = 0, best = -1;
  int best_k = kBins / 2 - 1;
  for (int k = 0; k < kBins - 1; ++k) {
    w0 += hist[k];
    sum0 += k * hist[k];
    const double w1 = n - w0;
    if (w0 == 0 || w1 == 0) continue;
    const double d = sum0 / w0 - (sum_all - sum0) / w1;
    const double between = w0 * w1 * d * d;
    if (between > best) best = between, best_k = k;
  }
  return static_cast<double>(best_k + 1) / kBins;
}

PhotoSegmentation segmentHoles(const GrayImage& image, const SegmentOptions& o) {
  if (image.width <= 2 || image.height <= 2 ||
      image.value.size() != static_cast<std::size_t>(image.width) * image.height)
    throw std::invalid_argument("the photograph is empty or smaller than 3 x 3 pixels");
  if (o.threshold >= 0 && !(o.threshold > 0 && o.threshold < 1))
    throw std::invalid_argument("the threshold must lie in (0, 1), got " +
                                std::to_string(o.threshold));
  const GrayImage s = smoothed(image);
  PhotoSegmentation out;
  out.width = image.width;
  out.height = image.height;
  out.automatic = o.threshold < 0;
  out.threshold = out.automatic ? otsuThreshold(s) : o.threshold;
  const int w = image.width, h = image.height;
  const std::size_t n = s.value.size();
  std::vector<std::uint8_t> hole_class(n);
  for (std::size_t p = 0; p < n; ++p)
    hole_class[p] = o.dark_holes ? s.value[p] < out.threshold : s.value[p] >= out.threshold;

  const std::size_t min_area = o.min_area_px > 0 ? static_cast<std::size_t>(o.min_area_px) : 25;
  out.label.assign(n, 0);
  std::vector<std::uint8_t> seen(n, 0);
  std::vector<std::size_t> stack, cells;
  for (std::size_t start = 0; start < n; ++start) {
    if (!hole_class[start] || seen[start]) continue;
    cells.clear();
    bool border = false;
    stack.push_back(start);
    seen[start] = 1;
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      cells.push_back(c);
      const int i = static_cast<int>(c % w), j = static_cast<int>(c / w);
      border |= i == 0 || j == 0 || i == w - 1 || j == h - 1;
      const int ni[4] = {i - 1, i + 1, i, i}, nj[4] = {j, j, j - 1, j + 1};
      for (int k = 0; k < 4; ++k) {
        if (ni[k] < 0 || nj[k] < 0 || ni[k] >= w || nj[k] >= h) continue;
        const std::size_t d = static_cast<std::size_t>(nj[k]) * w + ni[k];
        if (!hole_class[d] || seen[d]) continue;
        seen[d] = 1;
        stack.push_back(d);
      }
    }
    if (border || cells.size() < min_area) continue;
    PhotoHole hole;
    hole.area_px = static_cast<double>(cells.size());
    for (std::size_t c : cells) {
      out.label[c] = static_cast<int>(out.holes.size()) + 1;
      hole.centroid_px += Eigen::Vector2d(c % w + 0.5, c / w + 0.5);
    }
    hole.centroid_px /= hole.area_px;
    out.holes.push_back(hole);
  }
  // Largest first, and the labels renumbered to match.
  std::vector<std::size_t> order(out.holes.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return out.holes[a].area_px > out.holes[b].area_px;
  });
  std::vector<int> relabel(order.size() + 1, 0);
  std::vector<PhotoHole> sorted;
  for (std::size_t k = 0; k < order.size(); ++k) {
    relabel[order[k] + 1] = static_cast<int>(k) + 1;
    sorted.push_back(out.holes[order[k]]);
  }
  out.holes = std::move(sorted);
  for (int& l : out.label) l = relabel[l];
  return out;
}

SimulatedPlate simulatedPlate(const std::vector<Vec3>& x,
                              const std::vector<std::array<int, 4>>& tets,
                              const HoleOptions& options) {
  SimulatedPlate out;
  out.holes = findHoles(x, tets, options);
  if (tets.empty()) return out;
  std::vector<char> used(x.size(), 0);
  for (const auto& t : tets)
    for (int k : t) used[k] = 1;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!used[k]) continue;
    for (int m = 0; m < (options.mirror ? 2 : 1); ++m) {
      Vec3 p = x[k];
      if (m == 1) p[options.symmetry_axis] = 2 * options.symmetry_position - p[options.symmetry_axis];
      const Eigen::Vector2d q = out.holes.inPlane(p);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  out.centre = 0.5 * (lo + hi);
  out.half_size = 0.5 * (hi - lo);
  return out;
}

SimulatedPlate simulatedParticlePlate(const std::vector<DebrisParticle>& particles,
                                      const HoleOptions& options) {
  SimulatedPlate out;
  out.holes = findParticleHoles(particles, options);
  const PlateHoles& h = out.holes;
  out.centre = 0.5 * Eigen::Vector2d(h.u_min + h.u_max, h.v_min + h.v_max);
  out.half_size = Eigen::Vector2d(h.halfU(), h.halfV());
  return out;
}

Eigen::Vector2d PhotoFrame::toPlate(const Eigen::Vector2d& px) const {
  const Eigen::Vector2d d = px - pixel_ref;
  return plate_ref + m_per_px * Eigen::Vector2d(rear ? -d.x() : d.x(), -d.y());
}

Eigen::Vector2d PhotoFrame::toPixel(const Eigen::Vector2d& uv) const {
  const Eigen::Vector2d d = (uv - plate_ref) / m_per_px;
  return pixel_ref + Eigen::Vector2d(rear ? -d.x() : d.x(), -d.y());
}

std::vector<int> fillPolygons(const std::vector<std::vector<Eigen::Vector2d>>& polygons,
                              int width, int height) {
  std::vector<int> label(static_cast<std::size_t>(width) * height, 0);
  std::vector<double> xs;
  for (std::size_t n = 0; n < polygons.size(); ++n) {
    const auto& poly = polygons[n];
    if (poly.size() < 3) continue;
    double ylo = 1e300, yhi = -1e300;
    for (const Eigen::Vector2d& p : poly) ylo = std::min(ylo, p.y()), yhi = std::max(yhi, p.y());
    const int j0 = std::max(0, static_cast<int>(std::floor(ylo)));
    const int j1 = std::min(height - 1, static_cast<int>(std::ceil(yhi)));
    for (int j = j0; j <= j1; ++j) {
      const double y = j + 0.5;
      xs.clear();
      for (std::size_t k = 0; k < poly.size(); ++k) {
        const Eigen::Vector2d& a = poly[k];
        const Eigen::Vector2d& b = poly[(k + 1) % poly.size()];
        if ((a.y() <= y) != (b.y() <= y))
          xs.push_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        // Pixels whose centre i + 0.5 lies in [xs[k], xs[k + 1]).
        const int i0 = std::max(0, static_cast<int>(std::ceil(xs[k] - 0.5)));
        const int i1 = std::min(width, static_cast<int>(std::ceil(xs[k + 1] - 0.5)));
        for (int i = i0; i < i1; ++i)
          label[static_cast<std::size_t>(j) * width + i] = static_cast<int>(n) + 1;
      }
    }
  }
  return label;
}

HoleComparison compareHoles(const PhotoSegmentation& photo, const SimulatedPlate& plate,
                            const CompareOptions& o) {
  if (!(o.m_per_px > 0) || !std::isfinite(o.m_per_px))
    throw std::invalid_argument("the photograph's scale must be a positive length per pixel");
  const PlateHoles& sim = plate.holes;
  // Plate coordinates from the plate's centre: what an experimenter measures from.
  const auto local = [&](const Vec3& p) { return Eigen::Vector2d(sim.inPlane(p) - plate.centre); };
  HoleComparison out;
  PhotoFrame& f = out.frame;
  f.m_per_px = o.m_per_px;
  f.rear = o.rear;
  if (o.centre_px) {
    f.pixel_ref = *o.centre_px;
  } else {
    if (photo.holes.empty() || sim.holes.empty())
      throw std::invalid_argument(
          std::string(photo.holes.empty() ? "no hole found in the photograph"
                                          : "the simulated plate has no through-hole") +
          ": the holes cannot be aligned; give the pixel of the plate's centre");
    f.pixel_ref = photo.holes.front().centroid_px;  // both sides' holes: largest first
    f.plate_ref = local(sim.holes.front().centroid);
  }

  const double px_area = o.m_per_px * o.m_per_px;
  for (const PhotoHole& h : photo.holes) {
    HoleSize s;
    s.area = h.area_px * px_area;
    s.diameter = std::sqrt(4 * s.area / kPi);
    s.centroid = f.toPlate(h.centroid_px);
    out.photo.push_back(s);
  }
  std::vector<std::vector<Eigen::Vector2d>> polygons;
  for (const Hole& h : sim.holes) {
    out.simulated.push_back({h.area, h.diameter, local(h.centroid)});
    std::vector<Eigen::Vector2d> poly;
    for (const Vec3& p : h.outline) poly.push_back(f.toPixel(local(p)));
    polygons.push_back(std::move(poly));
  }
  out.simulated_label = fillPolygons(polygons, photo.width, photo.height);
  // Pixels in both, by photographed hole (rows) and simulated hole (columns); and each hole's
  // own pixel count on this grid, so that a pair's IoU is measured as the whole map's.
  const std::size_t np = photo.holes.size(), ns = sim.holes.size();
  std::vector<std::size_t> both(np * ns, 0), photo_count(np, 0), sim_count(ns, 0);
  for (std::size_t p = 0; p < out.simulated_label.size(); ++p) {
    const int a = photo.label[p], b = out.simulated_label[p];
    out.photo_px += a > 0;
    out.simulated_px += b > 0;
    out.both_px += a > 0 && b > 0;
    if (a > 0) ++photo_count[a - 1];
    if (b > 0) ++sim_count[b - 1];
    if (a > 0 && b > 0) ++both[(a - 1) * ns + (b - 1)];
  }
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t k = 0; k < ns; ++k) {
      const std::size_t in_both = both[i * ns + k];
      if (in_both == 0) continue;
      const double either = static_cast<double>(photo_count[i] + sim_count[k] - in_both);
      out.pairs.push_back({i, k, static_cast<double>(in_both) * px_area,
                           static_cast<double>(in_both) / either});
    }
  std::stable_sort(out.pairs.begin(), out.pairs.end(),
                   [](const HolePair& a, const HolePair& b) { return a.overlap > b.overlap; });
  // Filled pixels against the outlines' own area (shoelace), in pixels.
  double outline_px = 0;
  for (const auto& poly : polygons) {
    double a2 = 0;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Eigen::Vector2d& p = poly[k];
      const Eigen::Vector2d& q = poly[(k + 1) % poly.size()];
      a2 += p.x() * q.y() - q.x() * p.y();
    }
    outline_px += 0.5 * std::abs(a2);
  }
  if (outline_px > 0)
    out.simulated_outside = std::max(0.0, 1 - static_cast<double>(out.simulated_px) / outline_px);
  const std::size_t either = out.photo_px + out.simulated_px - out.both_px;
  out.iou = either > 0 ? static_cast<double>(out.both_px) / static_cast<double>(either) : 0.0;
  return out;
}

std::vector<std::size_t> partnersOf(const HoleComparison& c, std::size_t hole, bool photo_side) {
  std::vector<std::size_t> out;
  for (const HolePair& p : c.pairs)
    if ((photo_side ? p.photo : p.simulated) == hole) out.push_back(photo_side ? p.simulated : p.photo);
  return out;
}

double nearestOther(const HoleComparison& c, std::size_t hole, bool photo_side) {
  const Eigen::Vector2d& at = (photo_side ? c.photo : c.simulated)[hole].centroid;
  double best = std::numeric_limits<double>::infinity();
  for (const HoleSize& h : photo_side ? c.simulated : c.photo)
    best = std::min(best, (h.centroid - at).norm());
  return best;
}

}  // namespace fesph
