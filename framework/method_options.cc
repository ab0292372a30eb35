#include "framework/method_options.h"

#include <algorithm>

#include "framework/error.h"

namespace kincal {

std::vector<std::string> SplitComma(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    out.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

std::vector<YAML::Node> OptionsPerMethod(const YAML::Node& root, const std::vector<std::string>& methods,
                                         const std::string& where, int line) {
  std::vector<YAML::Node> out(methods.size());
  if (!root || root.IsNull()) return out;
  if (!root.IsMap()) ThrowInputError(where, line, line, "expected a map of options");
  bool keyed = true;
  for (const auto& kv : root) {
    if (std::find(methods.begin(), methods.end(), kv.first.Scalar()) == methods.end()) keyed = false;
  }
  if (!keyed && methods.size() > 1) {
    ThrowInputError(where, line, line, "with several methods, the options must be keyed by method name");
  }
  for (size_t i = 0; i < methods.size(); ++i) {
    if (!keyed) {
      out[i] = root;
      continue;
    }
    // A method missing from the map gets no options (a null node): a const map's operator[] returns an
    // invalid node for a missing key, which every later use of it throws on.
    const YAML::Node n = root[methods[i]];
    if (n.IsDefined()) out[i] = n;
  }
  return out;
}

}  // namespace kincal
