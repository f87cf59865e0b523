#ifndef forma_base_parameter_override_h
#define forma_base_parameter_override_h

#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace forma
{
  /// Set one entry of a read parameter file from 'Section/Sub/Entry=value'
  /// (the command line's --set, and overrides of nested parameter files).
  /// Throws an error naming the assignment if it is malformed, the entry
  /// does not exist or the value does not match its pattern; `prm` is left
  /// at the top level either way.
  void
  set_entry(dealii::ParameterHandler &prm, const std::string &assignment);
} // namespace forma

#endif
