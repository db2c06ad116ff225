#include "core/sim/sparsity.hpp"

#include <algorithm>
#include <stdexcept>

namespace packsim {

JacobianPattern PatternBuilder::build(int local, int read) const {
  if (!(0 <= local && local <= read && read <= n_)) throw std::invalid_argument("PatternBuilder: bad local/read");
  std::vector<std::pair<int, int>> e = entries_;
  for (int j = 0; j < n_; ++j) e.emplace_back(j, j);
  for (const auto& [c, r] : e)
    if (c < 0 || c >= n_ || r < 0 || r >= n_) throw std::out_of_range("PatternBuilder: entry outside the matrix");
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  JacobianPattern p;
  p.n = n_;
  p.local = local;
  p.read = read;
  p.colptr.assign(static_cast<size_t>(n_) + 1, 0);
  p.rows.reserve(e.size());
  for (const auto& [c, r] : e) {
    ++p.colptr[static_cast<size_t>(c) + 1];
    p.rows.push_back(r);
  }
  for (int j = 0; j < n_; ++j) p.colptr[static_cast<size_t>(j) + 1] += p.colptr[static_cast<size_t>(j)];
  return p;
}

std::vector<std::vector<int>> colourColumns(const JacobianPattern& p) {
  // Row-wise view of the columns < local: rowCols[i] = the local columns in row i.
  std::vector<std::vector<int>> rowCols(static_cast<size_t>(p.n));
  for (int j = 0; j < p.n; ++j)
    for (int k = p.colptr[static_cast<size_t>(j)]; k < p.colptr[static_cast<size_t>(j) + 1]; ++k) {
      const int i = p.rows[static_cast<size_t>(k)];
      if (j < p.local && i >= p.local)
        throw std::invalid_argument("colourColumns: a loose row lists a column it shares with others");
      if (j < p.local) rowCols[static_cast<size_t>(i)].push_back(j);
    }
  std::vector<int> colour(static_cast<size_t>(p.local), -1);
  std::vector<int> forbiddenBy;  // forbiddenBy[c] == j: colour c is taken in one of column j's rows
  std::vector<std::vector<int>> groups;
  for (int j = 0; j < p.local; ++j) {
    for (int k = p.colptr[static_cast<size_t>(j)]; k < p.colptr[static_cast<size_t>(j) + 1]; ++k)
      for (int other : rowCols[static_cast<size_t>(p.rows[static_cast<size_t>(k)])]) {
        if (other >= j) break;  // each row's columns are in order: the rest have no colour yet
        forbiddenBy[static_cast<size_t>(colour[static_cast<size_t>(other)])] = j;
      }
    int c = 0;
    while (c < static_cast<int>(groups.size()) && forbiddenBy[static_cast<size_t>(c)] == j) ++c;
    if (c == static_cast<int>(groups.size())) {
      groups.emplace_back();
      forbiddenBy.push_back(-1);
    }
    colour[static_cast<size_t>(j)] = c;
    groups[static_cast<size_t>(c)].push_back(j);
  }
  for (int j = p.local; j < p.read; ++j) groups.push_back({j});
  return groups;
}

}  // namespace packsim
