// Prints a meshlabserver 2020.09 script (.mlx) for one of our filters, every parameter listed
// (meshlabserver asserts on a missing one) at its default unless overridden:
//   write_mlx smooth|saliency [name=value ...]
// Values as filter_parameters.h's parseParameter reads them (choices by label, index or method
// key; on/off). examples/*.mlx are this tool's output (tests/e2e keep them in step).
#include <filter_saliency_bezier_smooth/filter_parameters.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>

using namespace saliency_bezier;

static std::string escape(const std::string &s) {
  std::string out;
  for (char c : s) {
    switch (c) {
    case '&': out += "&amp;"; break;
    case '<': out += "&lt;"; break;
    case '>': out += "&gt;"; break;
    case '"': out += "&quot;"; break;
    default: out += c;
    }
  }
  return out;
}

static std::string valueText(const ParamSpec &s, double value) {
  std::ostringstream o;
  switch (s.kind) {
  case ParamKind::Bool: o << (value != 0 ? "true" : "false"); break;
  case ParamKind::Int:
  case ParamKind::Enum: o << long(value); break;
  case ParamKind::Float: o << value; break;
  }
  return o.str();
}

static int usage() {
  std::cerr << "usage: write_mlx smooth|saliency [name=value ...]\n"
               "Prints a meshlabserver script for the filter, every parameter at its default "
               "unless given.\n\nsmooth ("
            << filterName(FilterId::SaliencyBezierSmooth) << "):\n"
            << parameterUsage(FilterId::SaliencyBezierSmooth) << "\nsaliency ("
            << filterName(FilterId::ComputeSaliencyCurvature) << "):\n"
            << parameterUsage(FilterId::ComputeSaliencyCurvature)
            << "\nExample: write_mlx smooth placement=organic iterations=6 "
               "preserve_volume=off\n";
  return 2;
}

int main(int argc, char **argv) {
  if (argc < 2 || (std::strcmp(argv[1], "smooth") && std::strcmp(argv[1], "saliency")))
    return usage();
  const FilterId id = std::strcmp(argv[1], "smooth") == 0 ? FilterId::SaliencyBezierSmooth
                                                          : FilterId::ComputeSaliencyCurvature;
  ParameterValues values;
  for (const ParamSpec &s : parameterSpecs(id)) values[s.name] = s.default_value;
  for (int a = 2; a < argc; ++a) {
    const std::string arg = argv[a];
    const size_t eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    const ParamSpec *spec = nullptr;
    for (const ParamSpec &s : parameterSpecs(id))
      if (s.name == name) spec = &s;
    if (eq == std::string::npos || !spec) {
      std::cerr << "write_mlx: '" << arg << "' is not name=value with a parameter of '"
                << filterName(id) << "'; they are:\n"
                << parameterUsage(id);
      return 2;
    }
    const std::string error = parseParameter(*spec, arg.substr(eq + 1), values[name]);
    if (!error.empty()) {
      std::cerr << "write_mlx: " << error << "\n";
      return 2;
    }
  }
  std::cout << "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"" << filterName(id)
            << "\">\n";
  for (const ParamSpec &s : parameterSpecs(id)) {
    static const char *types[] = {"RichInt", "RichFloat", "RichBool", "RichEnum"};
    std::cout << "  <Param name=\"" << s.name << "\" type=\"" << types[int(s.kind)]
              << "\" value=\"" << valueText(s, values[s.name]) << "\"";
    if (s.kind == ParamKind::Enum) {
      std::cout << " enum_cardinality=\"" << s.choices.size() << "\"";
      for (size_t c = 0; c < s.choices.size(); ++c)
        std::cout << " enum_val" << c << "=\"" << escape(s.choices[c]) << "\"";
    }
    std::cout << " description=\"" << escape(s.label) << "\"/>\n";
  }
  std::cout << " </filter>\n</FilterScript>\n";
  return 0;
}
