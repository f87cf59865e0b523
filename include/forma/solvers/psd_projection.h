#ifndef forma_solvers_psd_projection_h
#define forma_solvers_psd_projection_h

#include <string>

namespace dealii
{
  template <typename number>
  class FullMatrix;
}

namespace forma
{
  /**
   * Remove the negative part of a symmetric matrix, H - sum_{lambda_i < 0}
   * lambda_i v_i v_i^T (projected Newton: element or pair Hessians of
   * nonconvex energies made positive semidefinite before assembly). H is
   * symmetrized first; a non-finite entry throws a message naming `what`.
   */
  void
  project_to_psd(dealii::FullMatrix<double> &H, const std::string &what);
} // namespace forma

#endif
