#include <forma/adjoint/form.h>
#include <forma/adjoint/registry.h>

#include <cmath>

namespace forma
{
  using namespace dealii;

  std::vector<std::string> &
  registration_conflicts()
  {
    static std::vector<std::string> names;
    return names;
  }



  double
  KeyValueRecord::key(const std::string &k, const double fallback) const
  {
    read.insert(k);
    if (keys.count(k))
      return keys.at(k);
    AssertThrow(!std::isnan(fallback),
                ExcMessage(where + ": the key '" + k + "' is required."));
    return fallback;
  }



  unsigned int
  KeyValueRecord::id(const std::string &k) const
  {
    const double v = key(k);
    AssertThrow(v >= 0 && v < 255 && v == std::floor(v),
                ExcMessage(where + ": '" + k +
                           "' must be an id (an integer >= 0)."));
    return static_cast<unsigned int>(v);
  }

  template class Registry<Form<2>, const FormRecord<2> &>;
  template class Registry<Form<3>, const FormRecord<3> &>;
} // namespace forma
