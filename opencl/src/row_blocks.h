#pragma once
// Work split shared by the blocked kernels of norm.cl, loss.cl and reduce.cl.
//
// Reductions: a row of `length` elements is cut into `groups` blocks of kGroupSize work items;
// block b covers the kGroupSize * kVec * perItem elements from b * kGroupSize * kVec * perItem
// and item j reads the REAL4 vectors j, j + kGroupSize, ... of its block (up to perItem of
// them); the block's last < 4 elements (past its last full vector) are read by item 0. Adjacent
// items read adjacent vectors (coalesced on GPUs) and the explicit vectors keep PoCL's CPU code
// SIMD, which it does not manage across work items for these kernels (measured: 3-4x faster than
// scalar items). Each block's partial result lands in a fixed slot, so sums are deterministic run
// to run.
//
// Elementwise passes: 2-D launches (vector index within a row, row); the item just past a
// row's last full vector handles the row's last < 4 elements.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace simpli::ocl {

constexpr int kGroupSize = 64; ///< must match GROUP in norm.cl and loss.cl
constexpr int kVec = 4;        ///< REAL4

struct RowBlocks {
  int perItem = 1; ///< vectors per item
  int groups = 1;  ///< blocks per row
};

/// Aims at ~128 blocks per row for long rows (parallel work for any device) with 1..16
/// vectors per item (a block of at most 4096 elements stays in L1 between the two passes of
/// the statistics kernels).
inline RowBlocks rowBlocks(int64_t length) {
  const int64_t perGroupTarget = 128;
  const int64_t unit = kGroupSize * kVec;
  int64_t perItem = (length + unit * perGroupTarget - 1) / (unit * perGroupTarget);
  perItem = std::clamp<int64_t>(perItem, 1, 16);
  const int64_t block = unit * perItem;
  RowBlocks r;
  r.perItem = static_cast<int>(perItem);
  r.groups = static_cast<int>(std::max<int64_t>(1, (length + block - 1) / block));
  return r;
}

/// Items along a row for an elementwise pass: one per full vector plus one for the tail.
inline int64_t rowItems(int64_t length) {
  return length / kVec + 1;
}

/// Local size of the 2-D (row items, rows) launches: 64 items along a row when rows are long,
/// else fewer along the row and more rows per group (a small fixed set: PoCL compiles a
/// kernel per local size).
inline std::pair<std::size_t, std::size_t> rowLocal(int64_t itemsPerRow) {
  const std::size_t l0 = itemsPerRow >= 64 ? 64 : itemsPerRow >= 16 ? 16 : itemsPerRow >= 4 ? 4 : 1;
  return {l0, static_cast<std::size_t>(kGroupSize) / l0};
}

} // namespace simpli::ocl
