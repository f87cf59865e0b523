#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/parameter_override.h>

namespace forma
{
  void
  set_entry(dealii::ParameterHandler &prm, const std::string &assignment)
  {
    const auto eq = assignment.find('=');
    AssertThrow(eq != std::string::npos,
                dealii::ExcMessage("'" + assignment +
                                   "' is not of the form "
                                   "'Section/Entry=value'"));
    const auto path =
      dealii::Utilities::split_string_list(assignment.substr(0, eq), '/');
    const std::string value =
      dealii::Utilities::trim(assignment.substr(eq + 1));
    AssertThrow(!path.empty() && !path.back().empty(),
                dealii::ExcMessage("'" + assignment + "' names no entry"));
    unsigned int entered = 0;
    try
      {
        for (; entered + 1 < path.size(); ++entered)
          prm.enter_subsection(path[entered]);
        prm.set(path.back(), value);
      }
    catch (const std::exception &exc)
      {
        for (; entered > 0; --entered)
          prm.leave_subsection();
        AssertThrow(false,
                    dealii::ExcMessage("'" + assignment +
                                       "': " + error_message(exc)));
      }
    for (; entered > 0; --entered)
      prm.leave_subsection();
  }
} // namespace forma
