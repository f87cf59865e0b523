#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/base/records.h>
#include <forma/rhombic/parameter_ranges.h>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    std::array<std::optional<std::string>, RhombicStructure::n_parameters>
    parse_parameter_assignments(const std::string &text,
                                const std::string &entry)
    {
      std::array<std::optional<std::string>, RhombicStructure::n_parameters>
        result;
      for (const auto &item : Utilities::split_string_list(text))
        {
          const auto parts = Utilities::split_string_list(item, '=');
          AssertThrow(parts.size() == 2,
                      ExcMessage(entry + ": '" + item +
                                 "' is not of the form 'p1 = ...'"));
          const unsigned int i =
            RhombicStructure::parameter_index(parts[0], entry);
          AssertThrow(!result[i],
                      ExcMessage(entry + ": " + parts[0] + " appears twice"));
          result[i] = parts[1];
        }
      return result;
    }



    ParameterRanges
    parse_parameter_ranges(const std::string     &text,
                           const std::string     &entry,
                           const ParameterRanges &defaults,
                           const ParameterRanges &within)
    {
      auto       ranges = defaults;
      const auto texts  = parse_parameter_assignments(text, entry);
      for (unsigned int i = 0; i < texts.size(); ++i)
        if (texts[i])
          {
            const auto name  = RhombicStructure::parameter_name(i);
            const auto parts = Utilities::split_string_list(*texts[i], ':');
            AssertThrow(parts.size() == 2,
                        ExcMessage(entry + ": " + name + " = '" + *texts[i] +
                                   "' is not a range 'lo:hi'"));
            std::array<double, 2> r;
            for (unsigned int k = 0; k < 2; ++k)
              {
                const auto v = parse_values(parts[k], entry);
                AssertThrow(v.size() == 1,
                            ExcMessage(entry + ": " + name + " = '" +
                                       *texts[i] + "' is not a range 'lo:hi'"));
                r[k] = v[0];
              }
            AssertThrow(
              r[0] < r[1] && r[0] >= within[i][0] && r[1] <= within[i][1],
              ExcMessage(entry + ": " + name + " = " + sig(r[0]) + ":" +
                         sig(r[1]) + " is not an increasing range inside [" +
                         sig(within[i][0]) + ", " + sig(within[i][1]) + "]"));
            ranges[i] = r;
          }
      return ranges;
    }
  } // namespace rhombic
} // namespace forma
