#include <deal.II/base/parameter_handler.h>

#include <forma/base/parameter_reference.h>

#include <nlohmann/json.hpp>

#include <ostream>
#include <sstream>

namespace forma
{
  namespace
  {
    using Json = nlohmann::ordered_json;

    /// `text` as inline code inside a Markdown table cell: only `|` is
    /// escaped (entities would show literally), and the fence is longer
    /// than any run of backticks in the text.
    std::string
    code_cell(const std::string &text)
    {
      if (text.empty())
        return "*(empty)*";
      std::string fence = "`", escaped;
      for (std::size_t i = 0, run = 0; i < text.size(); ++i)
        {
          run = (text[i] == '`') ? run + 1 : 0;
          if (run >= fence.size())
            fence += '`';
          escaped +=
            (text[i] == '|') ? std::string("\\|") : std::string(1, text[i]);
        }
      const std::string pad =
        (text.front() == '`' || text.back() == '`') ? " " : "";
      return fence + pad + escaped + pad + fence;
    }

    /// Text safe inside a Markdown table cell.
    std::string
    cell(std::string text)
    {
      std::string result;
      for (const char c : text)
        if (c == '|')
          result += "\\|";
        else if (c == '<')
          result += "&lt;";
        else if (c == '>')
          result += "&gt;";
        else if (c == '\n')
          result += ' ';
        else
          result += c;
      return result;
    }

    /// deal.II's "[Selection a|b ]" and friends, without the brackets.
    std::string
    allowed_values(const std::string &pattern)
    {
      std::string p = pattern;
      if (p.size() >= 2 && p.front() == '[' && p.back() == ']')
        p = p.substr(1, p.size() - 2);
      while (!p.empty() && p.back() == ' ')
        p.pop_back();
      return p;
    }

    bool
    is_entry(const Json &node)
    {
      return node.is_object() && node.contains("default_value");
    }

    void
    write_section(std::ostream      &out,
                  const Json        &section,
                  const std::string &path)
    {
      bool has_entries = false;
      for (const auto &[name, node] : section.items())
        has_entries |= is_entry(node);
      if (has_entries)
        {
          out << "\n## " << (path.empty() ? "Top level" : path) << "\n\n"
              << "| entry | default | allowed values | description |\n"
              << "|---|---|---|---|\n";
          for (const auto &[name, node] : section.items())
            if (is_entry(node))
              {
                out << "| " << code_cell(name) << " | "
                    << code_cell(node["default_value"].get<std::string>())
                    << " | "
                    << cell(allowed_values(
                         node.value("pattern_description", std::string())))
                    << " | " << cell(node.value("documentation", std::string()))
                    << " |\n";
              }
        }
      for (const auto &[name, node] : section.items())
        if (node.is_object() && !is_entry(node))
          write_section(out, node, path.empty() ? name : path + " / " + name);
    }
  } // namespace



  void
  write_parameter_reference(std::ostream                   &out,
                            const dealii::ParameterHandler &prm,
                            const std::string              &application,
                            const std::string              &description)
  {
    std::ostringstream json;
    prm.print_parameters(json,
                         dealii::ParameterHandler::JSON |
                           dealii::ParameterHandler::KeepDeclarationOrder);
    out << "# " << application << ": parameter reference\n\n"
        << description << "\n\n"
        << "Generated from the code by `" << application
        << " --parameter-reference` (do not edit: "
           "`contrib/doc/update_parameter_reference.sh` rewrites it, and "
           "`tests/transient_ipc/parameter_reference` fails when it is "
           "stale). Sections are written `Section / Subsection`, as in "
           "`--set 'Section/Subsection/Entry=value'`.\n";
    write_section(out, Json::parse(json.str()), "");
  }
} // namespace forma
