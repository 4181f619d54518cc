#include "cell_marcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace semfuse::render::detail {
namespace {

constexpr int kLeafMask = CrossingCells::kLeafDim - 1;
constexpr int kMaxNewtonSteps = 4;
constexpr double kRootTolerance = 1e-4;  // of the segment through the cell
constexpr int kMaxCubeDim = 8;           // a leaf
constexpr double kInf = std::numeric_limits<double>::infinity();

int floorInt(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}

// The DDA's state between steps: the current cell, the ray parameter at which the ray leaves it
// along each axis, and the spacing of successive cell faces along each axis.
struct CellWalk {
  int cell[3];
  int step[3];
  double t_next[3];
  double t_delta[3];

  int exitAxis() const {
    return t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
  }
  // Moves to the first cell past the aligned cube of edge `dim` cells that holds the current one;
  // returns the ray parameter where it enters that cell. Counting the faces crossed per axis
  // (instead of locating the exit point with floor()) keeps cell and t_next consistent.
  double leaveCube(int dim) {
    int to_face[3];
    double t_face[3];
    for (int a = 0; a < 3; ++a) {
      const int within = cell[a] & (dim - 1);
      to_face[a] = step[a] > 0 ? dim - 1 - within : within;
      // Infinite where the ray does not move along a (0 x infinity would be NaN, and a NaN here
      // would pick the wrong exit face).
      t_face[a] = step[a] == 0 ? kInf : t_next[a] + to_face[a] * t_delta[a];
    }
    const int exit = t_face[0] < t_face[1] ? (t_face[0] < t_face[2] ? 0 : 2) : (t_face[1] < t_face[2] ? 1 : 2);
    const double t_exit = t_face[exit];
    for (int a = 0; a < 3; ++a) {
      if (a == exit || step[a] == 0) continue;  // (0 x infinite t_delta would make t_next NaN)
      // Faces t_next + j t_delta, j < to_face, at or before the exit (a fixed-length count:
      // the number varies from ray to ray, and a loop that stops at it mispredicts).
      int crossed = 0;
      for (int j = 0; j < kMaxCubeDim - 1; ++j)
        crossed += static_cast<int>(j < to_face[a]) & static_cast<int>(t_next[a] + j * t_delta[a] <= t_exit);
      cell[a] += crossed * step[a];
      t_next[a] += crossed * t_delta[a];
    }
    cell[exit] += (to_face[exit] + 1) * step[exit];
    t_next[exit] += (to_face[exit] + 1) * t_delta[exit];
    return t_exit;
  }
};

// The trilinear interpolant of a cell's corners as a polynomial in the cell-local position:
// f = c0 + c1 x + c2 y + c3 z + c4 xy + c5 xz + c6 yz + c7 xyz (corner k = dx + 2 dy + 4 dz).
struct CellPolynomial {
  double c0, c1, c2, c3, c4, c5, c6, c7;

  explicit CellPolynomial(const float v[8])
      : c0(v[0]),
        c1(v[1] - v[0]),
        c2(v[2] - v[0]),
        c3(v[4] - v[0]),
        c4(v[3] - v[2] - v[1] + v[0]),
        c5(v[5] - v[4] - v[1] + v[0]),
        c6(v[6] - v[4] - v[2] + v[0]),
        c7(v[7] - v[6] - v[5] + v[4] - v[3] + v[2] + v[1] - v[0]) {}
};

// That interpolant along a segment inside the cell, as a cubic g(s) = a0 + a1 s + a2 s^2 + a3 s^3
// for s in [0, 1], from the segment's start (cell-local) and its extent: a0 is the value at the
// start, a1 the gradient there along the extent, a2 and a3 the cross terms. g(0) and g(1) are
// the values where a ray enters and leaves the cell, so one cubic per cell answers all the walk
// asks of it.
struct SegmentCubic {
  double a0, a1, a2, a3;

  double value(double s) const { return a0 + s * (a1 + s * (a2 + s * a3)); }
  double slope(double s) const { return a1 + s * (2.0 * a2 + s * (3.0 * a3)); }
};
SegmentCubic segmentCubic(const CellPolynomial& p, const double start[3], const double extent[3]) {
  const double x = start[0], y = start[1], z = start[2], ax = extent[0], ay = extent[1], az = extent[2];
  const double xy = x * y, xz = x * z, yz = y * z;
  // The partial derivatives at the start.
  const double dfdx = p.c1 + p.c4 * y + p.c5 * z + p.c7 * yz;
  const double dfdy = p.c2 + p.c4 * x + p.c6 * z + p.c7 * xz;
  const double dfdz = p.c3 + p.c5 * x + p.c6 * y + p.c7 * xy;
  const double axay = ax * ay, axaz = ax * az, ayaz = ay * az;
  SegmentCubic g;
  g.a0 = p.c0 + x * dfdx + y * (p.c2 + p.c6 * z) + p.c3 * z;
  g.a1 = ax * dfdx + ay * dfdy + az * dfdz;
  g.a2 = p.c4 * axay + p.c5 * axaz + p.c6 * ayaz + p.c7 * (x * ayaz + y * axaz + z * axay);
  g.a3 = p.c7 * axay * az;
  return g;
}

// True when g, at least `lowest_end` > 0 at both ends of [0, 1], cannot reach zero in between:
// |g''| <= 2 |a2| + 6 |a3| on [0, 1], and g >= min(g(0), g(1)) - max|g''| / 8 there. Most
// crossing cells a ray passes on their positive side are settled by this, without looking for
// the cubic's interior minimum.
bool curvatureKeepsPositive(double a2, double a3, double lowest_end) {
  return lowest_end > 0.25 * std::abs(a2) + 0.75 * std::abs(a3);
}

// Where g, positive at both ends of [0, 1] and not settled by curvatureKeepsPositive, has an
// interior minimum that is not positive: a ray that enters and leaves a cell on the positive side
// can still cut through the surface in between (grazing a thin or curved piece of it). -1 when g
// stays positive.
double lowestInteriorPoint(const SegmentCubic& g) {
  // Stationary points: roots of g'(s) = a1 + 2 a2 s + 3 a3 s^2.
  double roots[2];
  int count = 0;
  constexpr double kFlat = 1e-12;
  if (std::abs(g.a3) > kFlat) {
    const double discriminant = g.a2 * g.a2 - 3.0 * g.a1 * g.a3;
    if (discriminant >= 0.0) {
      const double r = std::sqrt(discriminant);
      roots[count++] = (-g.a2 - r) / (3.0 * g.a3);
      roots[count++] = (-g.a2 + r) / (3.0 * g.a3);
    }
  } else if (std::abs(g.a2) > kFlat) {
    roots[count++] = -g.a1 / (2.0 * g.a2);
  }
  double lowest = -1.0, lowest_value = 0.0;
  for (int i = 0; i < count; ++i)
    if (roots[i] > 0.0 && roots[i] < 1.0 && g.value(roots[i]) <= lowest_value) {
      lowest = roots[i];
      lowest_value = g.value(roots[i]);
    }
  return lowest;
}

// A root of g in [0, hi], g(0) > 0 >= g(hi), to kRootTolerance by halving the bracket.
double bisectRoot(const SegmentCubic& g, double hi) {
  double lo = 0.0;
  while (hi - lo > kRootTolerance) {
    const double mid = 0.5 * (lo + hi);
    (g.value(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The root of g in [0, hi], where g(0) = g_lo > 0 >= g(hi) = g_hi: the secant through the ends,
// then Newton steps on the cubic (Horner's rule: far less work than interpolating the corners
// again) until a step moves less than kRootTolerance. Along a cell the interpolant is close to
// linear almost everywhere, so one step nearly always ends it: a short chain of dependent
// operations, which is what the ray waits for, and no branch that mispredicts. A step that would
// leave [0, hi] (a strongly curved cubic, a flat slope) hands over to bisection, which cannot.
double rootInBracket(const SegmentCubic& g, double hi, double g_lo, double g_hi) {
  double s = hi * g_lo / (g_lo - g_hi);
  for (int i = 0; i < kMaxNewtonSteps; ++i) {
    const double next = s - g.value(s) / g.slope(s);
    if (!(next >= 0.0 && next <= hi)) return bisectRoot(g, hi);
    const double moved = std::abs(next - s);
    s = next;
    if (moved < kRootTolerance) break;
  }
  return s;
}

}  // namespace

bool CellMarcher::findSurface(const MarchRay& ray, SurfaceHit& hit) const {
  if (!(ray.t_min < ray.t_max)) return false;
  const Eigen::Vector3d o = ray.origin * inv_voxel_size_;
  const Eigen::Vector3d d = ray.direction * inv_voxel_size_;

  double t = ray.t_min;
  const Eigen::Vector3d start = o + t * d;
  CellWalk walk{{floorInt(start.x()), floorInt(start.y()), floorInt(start.z())}, {}, {}, {}};
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0.0) {
      walk.step[a] = 1;
      walk.t_delta[a] = 1.0 / d[a];
      walk.t_next[a] = (walk.cell[a] + 1 - o[a]) * walk.t_delta[a];
    } else if (d[a] < 0.0) {
      walk.step[a] = -1;
      walk.t_delta[a] = -1.0 / d[a];
      walk.t_next[a] = (o[a] - walk.cell[a]) * walk.t_delta[a];
    } else {
      walk.step[a] = 0;
      walk.t_delta[a] = kInf;
      walk.t_next[a] = kInf;
    }
  }
  int* const cell = walk.cell;
  openvdb::Coord leaf_origin(cell[0] & ~kLeafMask, cell[1] & ~kLeafMask, cell[2] & ~kLeafMask);
  const CrossingCells::LeafCells* leaf = cells_->find(leaf_origin);

  // A ray crosses at most (t_max - t_min) (|dx| + |dy| + |dz|) + 3 cell faces; twice that bounds
  // the loop whatever the floating point does at faces (a guard: the walk must never hang a query).
  const double faces = (ray.t_max - ray.t_min) * (std::abs(d.x()) + std::abs(d.y()) + std::abs(d.z()));
  const long max_steps = 2 * static_cast<long>(std::min(faces, 1e9)) + 16;
  for (long steps = 0; steps < max_steps; ++steps) {
    const int lx = cell[0] & kLeafMask, ly = cell[1] & kLeafMask, lz = cell[2] & kLeafMask;
    const int empty_dim = leaf ? leaf->emptyBlockDim(lx, ly, lz) : CrossingCells::kLeafDim;
    if (empty_dim > 1) {
      // No crossing cell in the block around this one: jump over all of it.
      t = walk.leaveCube(empty_dim);
      if (t >= ray.t_max) return false;
    } else {
      const int axis = walk.exitAxis();
      const double t_exit = std::min(walk.t_next[axis], ray.t_max);
      if (leaf->isCrossing(lx, ly, lz)) {
        // The cell's corners k = dx + 2 dy + 4 dz, from the leaf's brick.
        const float* base = leaf->tsdf + CrossingCells::kBrickStride * lx + CrossingCells::kBrickDim * ly + lz;
        constexpr int kX = CrossingCells::kBrickStride, kY = CrossingCells::kBrickDim;
        const float v[8] = {base[0], base[kX],     base[kY],     base[kX + kY],
                            base[1], base[kX + 1], base[kY + 1], base[kX + kY + 1]};
        // The ray relative to the cell's base voxel, and its segment through the cell: the
        // interpolant along it is a cubic g in s = (t' - t) / (t_exit - t).
        const double rx = o.x() - cell[0], ry = o.y() - cell[1], rz = o.z() - cell[2];
        const double start[3] = {rx + t * d.x(), ry + t * d.y(), rz + t * d.z()};
        const double extent[3] = {(t_exit - t) * d.x(), (t_exit - t) * d.y(), (t_exit - t) * d.z()};
        const SegmentCubic g = segmentCubic(CellPolynomial(v), start, extent);
        const double f_in = g.a0;
        if (f_in > 0.0) {
          const double f_out = g.value(1.0);
          // The bracket [0, s_end] of the crossing, with g(s_end) <= 0; none when s_end < 0.
          double s_end = -1.0, g_end = f_out;
          if (f_out <= 0.0) {
            s_end = 1.0;
          } else if (!curvatureKeepsPositive(g.a2, g.a3, std::min(f_in, f_out))) {
            // Positive where the ray leaves too: the surface may still dip across the ray in between.
            s_end = lowestInteriorPoint(g);
            if (s_end > 0.0) g_end = g.value(s_end);
          }
          if (s_end > 0.0) {
            // Shading reads the label of one of the cell's corners from the packed voxels, which
            // the walk has not touched: start loading their cache lines now, so that the root
            // finding below hides the miss. (z and z + 1 share a line.)
            for (int dx = 0; dx < 2; ++dx)
              for (int dy = 0; dy < 2; ++dy)
                if (const volume::PackedVoxel* voxels =
                        leaf->upper[CrossingCells::LeafCells::upperHolding(lx + dx, ly + dy, lz)])
                  __builtin_prefetch(voxels + CrossingCells::LeafCells::offsetInLeaf(lx + dx, ly + dy, lz));
            hit.t = t + rootInBracket(g, s_end, f_in, g_end) * (t_exit - t);
            hit.leaf = leaf;
            hit.local[0] = lx;
            hit.local[1] = ly;
            hit.local[2] = lz;
            std::copy(std::begin(v), std::end(v), hit.tsdf);
            hit.fraction[0] = static_cast<float>(std::clamp(rx + hit.t * d.x(), 0.0, 1.0));
            hit.fraction[1] = static_cast<float>(std::clamp(ry + hit.t * d.y(), 0.0, 1.0));
            hit.fraction[2] = static_cast<float>(std::clamp(rz + hit.t * d.z(), 0.0, 1.0));
            return true;
          }
        }
      }
      if (walk.t_next[axis] >= ray.t_max) return false;
      t = walk.t_next[axis];
      walk.t_next[axis] += walk.t_delta[axis];
      cell[axis] += walk.step[axis];
    }
    const openvdb::Coord origin(cell[0] & ~kLeafMask, cell[1] & ~kLeafMask, cell[2] & ~kLeafMask);
    if (origin != leaf_origin) {
      leaf_origin = origin;
      leaf = cells_->find(leaf_origin);
    }
  }
  return false;
}

}  // namespace semfuse::render::detail
