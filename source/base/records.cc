#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>
#include <deal.II/lac/vector.h>

#include <forma/base/application.h>
#include <forma/base/records.h>

#include <iomanip>
#include <sstream>

namespace forma
{
  using dealii::ExcMessage;

  std::vector<std::string>
  split_top_level(const std::string &text, const char separator)
  {
    std::vector<std::string> parts(1);
    int                      depth = 0;
    for (const char c : text)
      {
        if (c == '(')
          ++depth;
        else if (c == ')')
          --depth;
        if (c == separator && depth == 0)
          parts.emplace_back();
        else
          parts.back() += c;
      }
    for (auto &p : parts)
      p = dealii::Utilities::trim(p);
    return parts;
  }



  std::vector<Record>
  parse_records(const std::string &text,
                const unsigned int n_fields,
                const std::string &entry)
  {
    std::vector<Record> records;
    for (const auto &item : split_top_level(text, ';'))
      {
        if (item.empty())
          continue;
        const auto fields = split_top_level(item, ':');
        AssertThrow(fields.size() == n_fields + 1,
                    ExcMessage("'" + entry + "': the record '" + item +
                               "' should have " + std::to_string(n_fields + 1) +
                               " fields separated by ':'."));
        Record r;
        if (fields[0] == "*")
          {
            r.id = any_id;
            r.fields.assign(fields.begin() + 1, fields.end());
            records.push_back(r);
            continue;
          }
        try
          {
            const int id = dealii::Utilities::string_to_int(fields[0]);
            AssertThrow(id >= 0, ExcMessage("negative"));
            r.id = id;
          }
        catch (...)
          {
            AssertThrow(false,
                        ExcMessage(
                          "'" + entry + "': '" + fields[0] +
                          "' is not a valid id (a non-negative integer)."));
          }
        r.fields.assign(fields.begin() + 1, fields.end());
        records.push_back(r);
      }
    return records;
  }



  std::map<std::string, double>
  parse_key_values(const std::string &text, const std::string &entry)
  {
    std::map<std::string, double> values;
    for (const auto &item : split_top_level(text, ','))
      {
        if (item.empty())
          continue;
        const auto eq = item.find('=');
        AssertThrow(eq != std::string::npos,
                    ExcMessage("'" + entry +
                               "': expected 'name = value', got '" + item +
                               "'."));
        const std::string key = dealii::Utilities::trim(item.substr(0, eq));
        const std::string val = dealii::Utilities::trim(item.substr(eq + 1));
        try
          {
            values[key] = dealii::Utilities::string_to_double(val);
          }
        catch (...)
          {
            AssertThrow(false,
                        ExcMessage("'" + entry + "': the value '" + val +
                                   "' of '" + key + "' is not a number."));
          }
      }
    return values;
  }



  std::vector<bool>
  parse_components(const std::string &text,
                   const unsigned int dim,
                   const std::string &entry)
  {
    std::vector<bool> mask(dim, false);
    const std::string letters = "xyz";
    for (const char c : text)
      {
        if (std::isspace(static_cast<unsigned char>(c)) || c == ',')
          continue;
        const auto d = letters.find(c);
        AssertThrow(d != std::string::npos && d < dim,
                    ExcMessage("'" + entry + "': '" + text +
                               "' is not a component list; use letters from '" +
                               letters.substr(0, dim) + "'."));
        mask[d] = true;
      }
    return mask;
  }



  namespace
  {
    std::string
    join(const std::vector<std::string> &parts)
    {
      std::string out;
      for (const auto &p : parts)
        out += (out.empty() ? "" : ", ") + p;
      return out;
    }
  } // namespace



  template <int dim>
  std::unique_ptr<dealii::FunctionParser<dim>>
  make_function(const std::vector<std::string>      &expressions,
                const std::vector<bool>             &mask,
                const std::map<std::string, double> &constants,
                const std::string                   &entry)
  {
    const unsigned int n_masked = std::count(mask.begin(), mask.end(), true);
    AssertThrow(expressions.size() == n_masked,
                ExcMessage("'" + entry + "': " + std::to_string(n_masked) +
                           " expression(s) expected, one per component, but " +
                           std::to_string(expressions.size()) + " given."));
    std::vector<std::string> all(mask.size(), "0");
    for (unsigned int c = 0, k = 0; c < mask.size(); ++c)
      if (mask[c])
        all[c] = expressions[k++];

    const std::string variables = dim == 2 ? "x,y,t" : "x,y,z,t";
    auto f = std::make_unique<dealii::FunctionParser<dim>>(mask.size());
    try
      {
        auto with_pi = constants;
        with_pi.emplace("pi", dealii::numbers::PI);
        with_pi.emplace("Pi", dealii::numbers::PI);
        f->initialize(variables, all, with_pi, /*time_dependent=*/true);
        // muparser reports some errors only at evaluation.
        dealii::Vector<double> v(mask.size());
        f->vector_value(dealii::Point<dim>(), v);
      }
    catch (const std::exception &exc)
      {
        AssertThrow(false,
                    ExcMessage("'" + entry +
                               "': cannot use the expression(s) '" +
                               join(expressions) + "': " + error_message(exc)));
      }
    return f;
  }

  template std::unique_ptr<dealii::FunctionParser<2>>
  make_function<2>(const std::vector<std::string> &,
                   const std::vector<bool> &,
                   const std::map<std::string, double> &,
                   const std::string &);
  template std::unique_ptr<dealii::FunctionParser<3>>
  make_function<3>(const std::vector<std::string> &,
                   const std::vector<bool> &,
                   const std::map<std::string, double> &,
                   const std::string &);


  std::vector<double>
  parse_numbers(const std::string &text,
                const std::string &name,
                const double       lower,
                const double       upper)
  {
    std::vector<double> values;
    for (const auto &t : dealii::Utilities::split_string_list(text))
      {
        const auto v = parse_values(t, name);
        AssertThrow(v.size() == 1 && v[0] > lower && v[0] < upper,
                    ExcMessage(name + ": '" + t + "' is not one number in (" +
                               sig(lower) + ", " + sig(upper) + ")"));
        values.push_back(v[0]);
      }
    return values;
  }



  std::string
  path_relative_to(const std::string &directory, const std::string &file)
  {
    return file.empty() || file[0] == '/' ? file : directory + "/" + file;
  }



  std::string
  sig(const double x, const int digits)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
  }

  // "a:b:n" (n values from a to b) or a comma separated list.
  std::vector<double>
  parse_values(const std::string &text, const std::string &name)
  {
    std::vector<double> values;
    auto                number = [&](const std::string &t) {
      std::size_t used = 0;
      double      v    = 0;
      try
        {
          v = std::stod(t, &used);
        }
      catch (...)
        {
          used = 0;
        }
      AssertThrow(used == t.size() && !t.empty(),
                  ExcMessage(name + ": '" + t +
                             "' is not a number (use 'a:b:n' or a list)"));
      return v;
    };
    const std::string trimmed = dealii::Utilities::trim(text);
    if (trimmed.find(':') != std::string::npos)
      {
        const auto parts = dealii::Utilities::split_string_list(trimmed, ':');
        AssertThrow(parts.size() == 3,
                    ExcMessage(name + ": a range is 'a:b:n', got '" + trimmed +
                               "'"));
        const double       a = number(parts[0]), b = number(parts[1]);
        const double       nd = number(parts[2]);
        const unsigned int n  = static_cast<unsigned int>(nd);
        AssertThrow(n >= 1 && n == nd,
                    ExcMessage(name + ": the count in '" + trimmed +
                               "' must be a positive integer"));
        for (unsigned int k = 0; k < n; ++k)
          values.push_back(n == 1 ? a : a + (b - a) * k / (n - 1));
      }
    else
      for (const auto &t : dealii::Utilities::split_string_list(trimmed, ','))
        values.push_back(number(t));
    AssertThrow(!values.empty(), ExcMessage(name + " is empty"));
    return values;
  }

} // namespace forma
