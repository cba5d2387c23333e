#pragma once
/// Uniform Cartesian background grid with ghost ("extra") node layers, node fields as flat arrays.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <vector>

#include "mpm/core/types.hpp"

namespace mpm {

/// Geometry of a uniform grid: physical domain [lo, lo + cells*h] plus `ghost` extra node layers per side
/// (Steffen et al. 2008, Sec. 3.4.2). Node (i_0, ..., i_{D-1}) with -ghost <= i_d <= cells_d + ghost.
template <int Dim>
struct GridGeometry {
  Vec<Dim> lo =
      Vec<Dim>::Zero();  ///< position of the grid's node (0,...,0) [m] (a box's node 0 is at lo + h offset)
  Real h = 1.0;          ///< cell width [m], equal along every axis
  IVec<Dim> cells{};     ///< cells per axis in the physical domain
  int ghost = 1;         ///< extra node layers beyond each face
  /// Global index of node (0, ..., 0): the arrays are local to this box of the grid, node and cell indices in
  /// messages, checkpoints and outputs are global (zero in one process).
  IVec<Dim> offset{};
  /// Axes whose two faces are one periodic pair (Steffen et al. 2008, Sec. 4.3): node cells_d is node 0
  /// again, and a particle leaving through one face enters through the other.
  std::array<bool, Dim> periodic{};
  /// Faces (x-min, x-max, y-min, ...) that particles may cross: one that has is outside the grid and is
  /// removed after the step (Steffen et al. 2008, Sec. 3.4: material leaves through a free boundary).
  std::array<bool, 2 * Dim> outflow{};
  /// Faces that hold the material (a prescribed velocity, a Coulomb wall, a symmetry plane): a particle
  /// centre the nodes' velocity carries past one is put back on its plane. GIMP and B-spline weights reach
  /// beyond a particle's centre, so a centre pressed onto a wall moves with nodes inside the material and can
  /// cross it.
  std::array<bool, 2 * Dim> walls{};
  /// Faces where the B-spline kernels clamp their knots (bspline2-clamped, bspline3-clamped; Steffen et al.
  /// 2008, Sec. 4.3): no particle reaches a node beyond one, so the ghost layers there stay empty.
  std::array<bool, 2 * Dim> clamped{};

  /// Tiles: cubes of tile_width node layers per axis, the first starting at the first ghost layer (storage
  /// index 0). A P2G pass sums each tile's particles apart and adds the tiles' sums into the nodes in an
  /// order fixed by the tiles (ScatterOrder), so a box of whole tiles computes the same sums.
  static constexpr int tile_shift = 3, tile_width = 1 << tile_shift;
  /// A stencil packs its tile's flat index and its base node's coordinates in the tile (tile_shift bits per
  /// axis, for three axes) in 32 bits: (tile << slot_bits) | slot.
  static constexpr int slot_bits = 3 * tile_shift;
  static constexpr std::size_t max_tiles = std::size_t{1} << (31 - slot_bits);

  /// Node layers per axis this box of the grid holds, ghosts included; zero: the whole grid (one process). A
  /// box's first layer is the global layer `offset` (counted from the first ghost layer), a whole tile.
  IVec<Dim> box_nodes{};

  int nodes_along(int d) const { return box_nodes[d] > 0 ? box_nodes[d] : cells[d] + 1 + 2 * ghost; }
  int tiles_along(int d) const { return (nodes_along(d) + tile_width - 1) >> tile_shift; }
  std::size_t tile_count() const {
    std::size_t n = 1;
    for (int d = 0; d < Dim; ++d) n *= static_cast<std::size_t>(tiles_along(d));
    return n;
  }
  std::size_t node_count() const {
    std::size_t n = 1;
    for (int d = 0; d < Dim; ++d) n *= static_cast<std::size_t>(nodes_along(d));
    return n;
  }
  /// Flat-array stride of axis d (axis 0 varies fastest).
  std::ptrdiff_t stride(int d) const {
    std::ptrdiff_t s = 1;
    for (int e = 0; e < d; ++e) s *= nodes_along(e);
    return s;
  }
  /// Flat index of node with grid coordinates i (ghost nodes have negative or > cells coordinates).
  std::ptrdiff_t flat(const IVec<Dim>& i) const {
    std::ptrdiff_t f = 0;
    for (int d = Dim - 1; d >= 0; --d) f = f * nodes_along(d) + (i[d] + ghost);
    return f;
  }
  /// The global index of local node i.
  IVec<Dim> global(const IVec<Dim>& i) const {
    IVec<Dim> g;
    for (int d = 0; d < Dim; ++d) g[d] = i[d] + offset[d];
    return g;
  }
  /// Grid coordinates of a flat node index.
  IVec<Dim> coords(std::ptrdiff_t f) const {
    IVec<Dim> i;
    for (int d = 0; d < Dim; ++d) {
      i[d] = static_cast<int>(f % nodes_along(d)) - ghost;
      f /= nodes_along(d);
    }
    return i;
  }
  Vec<Dim> position(const IVec<Dim>& i) const {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = lo[d] + h * (i[d] + offset[d]);
    return x;
  }
  Vec<Dim> hi() const {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = lo[d] + h * cells[d];
    return x;
  }
  /// x brought into [lo, hi) along the periodic axes by one period (a particle moves less than a cell a
  /// step).
  Vec<Dim> wrap(Vec<Dim> x) const {
    for (int d = 0; d < Dim; ++d)
      if (periodic[d]) {
        const Real length = h * cells[d];
        if (x[d] >= lo[d] + length)
          x[d] -= length;
        else if (x[d] < lo[d])
          x[d] += length;
      }
    return x;
  }
  /// x put back on the plane of each wall it lies beyond (walls).
  Vec<Dim> onto_walls(Vec<Dim> x) const {
    for (int d = 0; d < Dim; ++d) {
      const Real top = lo[d] + h * cells[d];
      if (walls[2 * d] && x[d] < lo[d]) x[d] = lo[d];
      if (walls[2 * d + 1] && x[d] > top) x[d] = top;
    }
    return x;
  }
  /// True when x lies in the physical domain (boundary included).
  bool contains(const Vec<Dim>& x) const {
    for (int d = 0; d < Dim; ++d)
      if (!(x[d] >= lo[d] && x[d] <= lo[d] + h * cells[d])) return false;
    return true;
  }
  /// True when x lies outside the physical domain, beyond outflow faces only.
  bool beyond_outflow(const Vec<Dim>& x) const {
    bool beyond = false;
    for (int d = 0; d < Dim; ++d) {
      const bool below = x[d]<lo[d], above = x[d]> lo[d] + h * cells[d];
      if ((below && !outflow[2 * d]) || (above && !outflow[2 * d + 1]) || !(x[d] == x[d])) return false;
      beyond = beyond || below || above;
    }
    return beyond;
  }
};

/// The fields of one node in one time step. Kept together (one 64-byte line in 2-D) because every stage
/// touches several of them at once: P2G accumulates m, v and a; the grid update reads and writes all; G2P
/// gathers a and v_new. Measured against separate arrays per field, P2G ran 15-25% faster
/// (docs/performance.md). A 2-D node is aligned to its cache line, so that a transfer reads or writes it with
/// one 64-byte access that does not straddle two lines.
template <int Dim>
struct alignas(sizeof(Real) * (Dim == 2 ? 8 : 1)) GridNode {
  Real m = 0;                         ///< nodal mass m_i [kg]
  Vec<Dim> v = Vec<Dim>::Zero();      ///< momentum during P2G, then velocity v_i^n [m/s]
  Vec<Dim> a = Vec<Dim>::Zero();      ///< force f_i during P2G, then acceleration a_i [m/s^2]
  Vec<Dim> v_new = Vec<Dim>::Zero();  ///< time-advanced velocity v_i^* [m/s]
};

/// Where each field of a GridNode starts, in Reals from m (fixed-size Eigen vectors may be aligned to more
/// than one Real): the transfers add whole node records and address the fields by these slots
/// (transfer/p2g.hpp).
template <int Dim>
struct NodeSlots {
  static constexpr int align = static_cast<int>(alignof(Vec<Dim>) / sizeof(Real));
  static constexpr int up(int k) { return (k + align - 1) / align * align; }
  static constexpr int m = 0, v = up(1), a = up(v + Dim), v_new = up(a + Dim);
};
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winvalid-offsetof"  // GCC and Clang give the offsets of these plain members
static_assert(offsetof(GridNode<2>, v) == NodeSlots<2>::v * sizeof(Real) &&
              offsetof(GridNode<2>, a) == NodeSlots<2>::a * sizeof(Real) &&
              offsetof(GridNode<2>, v_new) == NodeSlots<2>::v_new * sizeof(Real));
static_assert(offsetof(GridNode<3>, v) == NodeSlots<3>::v * sizeof(Real) &&
              offsetof(GridNode<3>, a) == NodeSlots<3>::a * sizeof(Real) &&
              offsetof(GridNode<3>, v_new) == NodeSlots<3>::v_new * sizeof(Real));
static_assert(offsetof(GridNode<1>, v) == NodeSlots<1>::v * sizeof(Real) &&
              offsetof(GridNode<1>, a) == NodeSlots<1>::a * sizeof(Real) &&
              offsetof(GridNode<1>, v_new) == NodeSlots<1>::v_new * sizeof(Real));
#pragma GCC diagnostic pop

/// A node velocity field a stage reads: the projected (or re-projected) v, or the advanced v_new.
template <int Dim>
using NodeVelocity = Vec<Dim> GridNode<Dim>::*;

/// Which node fields a halo sum or a symmetry fold acts on.
enum class NodeFields { mass_momentum, force };

/// The background grid: its geometry and one GridNode per node (ghosts included), flat.
template <int Dim>
struct Grid {
  GridGeometry<Dim> geometry;
  std::vector<GridNode<Dim>> nodes;

  /// All bytes zero, padding included: transfers add whole node records (p2g).
  explicit Grid(const GridGeometry<Dim>& g) : geometry(g), nodes(g.node_count()) {
    std::memset(static_cast<void*>(nodes.data()), 0, bytes());
  }

  std::size_t size() const { return nodes.size(); }
  std::size_t bytes() const { return size() * sizeof(GridNode<Dim>); }
};

}  // namespace mpm
