#ifndef forma_base_parameter_reference_h
#define forma_base_parameter_reference_h

#include <iosfwd>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace forma
{
  /**
   * The parameter reference of an application as Markdown: every entry of
   * `prm` (as declared, in declaration order) with its default, its
   * allowed values and its documentation, one table per subsection.
   * doc/parameters/<app>.md is this output (`<app> --parameter-reference`),
   * and a test fails when the file no longer matches the code.
   */
  void
  write_parameter_reference(std::ostream                   &out,
                            const dealii::ParameterHandler &prm,
                            const std::string              &application,
                            const std::string              &description);
} // namespace forma

#endif
