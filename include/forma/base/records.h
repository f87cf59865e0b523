#ifndef forma_base_records_h
#define forma_base_records_h

#include <deal.II/base/function_parser.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace forma
{
  /**
   * Compact `.prm` syntax for lists of per-id settings:
   *   `set Dirichlet = 0 : xy : 0, 0 ; 2 : y : 0.1*t`
   * Records are separated by ';' and their fields by ':'; commas inside
   * parentheses (e.g. `if(t<1, t, 1)`) do not split an expression list.
   */
  std::vector<std::string>
  split_top_level(const std::string &text, const char separator);

  /// The id of a record written `* : ...`: it applies to every id not given.
  constexpr unsigned int any_id = static_cast<unsigned int>(-1);

  /// One record `id : fields...`, fields trimmed.
  struct Record
  {
    unsigned int             id;
    std::vector<std::string> fields;
  };

  /// Parse records with exactly `n_fields` fields after the id; `entry`
  /// names the parameter in error messages.
  std::vector<Record>
  parse_records(const std::string &text,
                const unsigned int n_fields,
                const std::string &entry);

  /// `a=1, b=2` into a map; `entry` names the parameter in error messages.
  std::map<std::string, double>
  parse_key_values(const std::string &text, const std::string &entry);

  /// A component mask from letters of "xyz" (e.g. "xz"), for `dim` components.
  std::vector<bool>
  parse_components(const std::string &text,
                   const unsigned int dim,
                   const std::string &entry);

  /**
   * A FunctionParser over (x, y[, z], t) with `n_components` expressions, or
   * one expression per masked component (`mask`), others zero. Throws a
   * message naming `entry` when an expression does not parse.
   */
  /// "a:b:n" (n values from a to b) or a comma separated list of numbers;
  /// `name` (section/entry) for the error message.
  std::vector<double>
  parse_values(const std::string &text, const std::string &name);

  /// A comma separated list of numbers, each in the open interval
  /// (lower, upper); empty text gives an empty list.
  std::vector<double>
  parse_numbers(const std::string &text,
                const std::string &name,
                const double       lower,
                const double       upper);

  /// x with `digits` significant digits.
  std::string
  sig(const double x, const int digits = 4);

  /// `file` as given if absolute or empty, else relative to `directory`
  /// (the parameter file's).
  std::string
  path_relative_to(const std::string &directory, const std::string &file);

  template <int dim>
  std::unique_ptr<dealii::FunctionParser<dim>>
  make_function(const std::vector<std::string>      &expressions,
                const std::vector<bool>             &mask,
                const std::map<std::string, double> &constants,
                const std::string                   &entry);
} // namespace forma

#endif
