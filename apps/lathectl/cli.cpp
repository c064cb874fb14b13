#include "cli.hpp"

#include <string>
#include <vector>

namespace lathectl::cli {

std::string doc(const std::string& page) {
  return "docs/" + page + " in the lathectl sources (installed: /usr/share/doc/lathectl/docs/" +
         page + ")";
}

std::string command_line_error(const CLI::App& app, const CLI::ParseError& e, int argc,
                               char** argv) {
  const CLI::App* cur = &app;
  std::vector<std::string> path;
  while (!cur->get_subcommands().empty()) {
    cur = cur->get_subcommands().front();
    path.push_back(cur->get_name());
  }
  std::string where;
  for (const auto& p : path) where += (where.empty() ? "" : " ") + p;
  std::string known;
  for (const auto* sub : cur->get_subcommands([](const CLI::App*) { return true; }))
    known += (known.empty() ? "" : ", ") + sub->get_name();
  if (!known.empty() && cur->get_subcommands().empty() && cur->get_require_subcommand_min() > 0) {
    // The first word that is neither an option nor the command path so far.
    std::size_t matched = 0;
    for (int i = 1; i < argc; ++i) {
      const std::string w = argv[i];
      if (w.empty() || w[0] == '-') continue;
      if (matched < path.size() && w == path[matched]) {
        ++matched;
        continue;
      }
      return "unknown command '" + (where.empty() ? w : where + " " + w) + "' (" + known + ")";
    }
    return (where.empty() ? "" : where + ": ") + "a command is required (" + known + ")";
  }
  std::string msg = e.what();
  if (dynamic_cast<const CLI::ValidationError*>(&e) && !msg.empty() && msg[0] == '-') {
    // "--d-mm: nan: expected ..." → "--d-mm nan: expected ... (spool diameter d)"
    const auto colon = msg.find(": ");
    const std::string name = msg.substr(0, colon);
    if (colon != std::string::npos) msg = name + " " + msg.substr(colon + 2);
    if (const CLI::Option* opt = cur->get_option_no_throw(name)) {
      std::string what = opt->get_description();
      what = what.substr(0, what.find(" ["));
      if (!what.empty()) msg += " (" + what + ")";
    }
  }
  for (auto& c : msg)
    if (c == '\n') c = ' ';
  return (where.empty() ? "" : where + ": ") + msg;
}

}  // namespace lathectl::cli
