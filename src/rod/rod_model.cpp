#include "traverse/rod/rod_model.hpp"

namespace traverse::rod {

int RodModel::node_row_count(int j) const {
  const int p = unknowns_per_node();
  if (num_cells == 0) return p;  // degenerate; not used
  if (j == 0) return carries_ys() ? 18 : 6;
  if (j == num_cells) return cell_rows() + 6;
  return cell_rows();
}

}  // namespace traverse::rod
