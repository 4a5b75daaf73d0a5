#pragma once
// Perfect lattices shared by the analysis tests.
#include <cmath>
#include <vector>

#include "granpack/core/cell.h"

namespace granpack::test {

/// Triangular lattice of unit spacing: nx x ny rectangular cells (1, sqrt 3) with 2 grains
/// each. Sets the cell and returns the scaled positions.
inline std::vector<Vec<2>> triangular_lattice(int nx, int ny, Cell<2>& cell) {
  cell.length = Vec<2>(nx, ny * std::sqrt(3.0));
  std::vector<Vec<2>> s;
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y) {
      s.push_back(Vec<2>((x + 0.0) / nx, (y + 0.0) / ny));
      s.push_back(Vec<2>((x + 0.5) / nx, (y + 0.5) / ny));
    }
  return s;
}

} // namespace granpack::test
