// The sparsity of an ODE's Jacobian df/dx and its column colouring, for a Jacobian
// filled by difference quotients (core/sim/cvode_jacobian.hpp).
//
// Columns in CSC form, rows sorted within a column; every diagonal entry is present
// (CVODE forms I - γJ in place, so the pattern never changes).
//
//   rows [0, local)      complete: such a row depends on no column it does not list
//   rows [local, n)      loose (thermal nodes linked to many cells, quadratures): may
//                        depend on any column, but list only columns >= local
//   columns [local, read) perturbed each alone, so the loose rows' entries are exact;
//                        a loose row's dependence on columns < local is left out (a
//                        weak coupling for CVODE's Newton iteration)
//   columns [read, n)    never read by the right-hand side (quadratures): zero
//
// Columns < local that share no row are perturbed together: one right-hand side per
// colour, and the number of colours depends on how many states couple, not on n.
#pragma once
#include <utility>
#include <vector>

namespace packsim {

struct JacobianPattern {
  int n = 0;
  int local = 0;
  int read = 0;
  std::vector<int> colptr;  // n + 1
  std::vector<int> rows;    // colptr[n]
  int nonzeros() const { return colptr.empty() ? 0 : colptr.back(); }
};

// Collects (row, column) entries; build() adds the diagonal, sorts and merges duplicates.
class PatternBuilder {
 public:
  explicit PatternBuilder(int n) : n_(n) {}
  void add(int row, int col) { entries_.emplace_back(col, row); }
  JacobianPattern build(int local, int read) const;

 private:
  int n_;
  std::vector<std::pair<int, int>> entries_;  // (column, row)
};

// Greedy colouring of the columns < local (in order: each takes the lowest colour none
// of its rows has yet), then each column in [local, read) as a colour of its own.
// Columns >= read are in none. Throws if a loose row lists a column < local.
std::vector<std::vector<int>> colourColumns(const JacobianPattern& p);

}  // namespace packsim
