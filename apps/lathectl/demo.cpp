// `lathectl demo [NAMES]`: every example scenario (or the ones named), in parallel, and an
// index.html linking their reports.
#include <algorithm>
#include <atomic>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cli.hpp"
#include "lathectl/core/parallel.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/install_paths.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/registry.hpp"

namespace fs = std::filesystem;

namespace lathectl::cli {
namespace {

// The example scenarios: the installed ones for an installed program, the source tree's for a
// build-tree program, $LATHECTL_EXAMPLES_DIR over both.
std::string examples_dir() {
  return io::locate_tree(
      "LATHECTL_EXAMPLES_DIR",
      {LATHECTL_EXAMPLES_DIR, LATHECTL_EXAMPLES_SUBDIR, LATHECTL_INSTALLED_EXAMPLES_DIR}, "");
}

// The description's first sentence, or its first words up to about 140 characters.
std::string first_sentence(const std::string& d) {
  const auto dot = d.find(". ");
  if (dot != std::string::npos && dot < 180) return d.substr(0, dot + 1);
  if (d.size() <= 160) return d;
  const auto cut = d.rfind(' ', 140);
  return d.substr(0, cut == std::string::npos ? 140 : cut) + " …";
}

// The demo index's entry for a run: ✔/✘ of its acceptance, what failed it, and a link to each
// unmet model check in its report (which does not decide the mark).
io::IndexEntry index_entry(const io::Scenario& sc, const io::RunOutput& r) {
  io::IndexEntry e;
  e.title = sc.name + " — " + first_sentence(sc.description);
  e.href = sc.name + "/report.html";
  e.summary = r.headline;
  e.status = r.verdict.ok() ? 1 : -1;
  e.verdict = r.verdict.line(false);
  // A failure on purpose (demonstrates_failure: no control, a sensor fault, a set-up forced
  // through) is what it shows, not a ✘; one that does not fail is.
  if (sc.demonstrates_failure) {
    e.status = r.verdict.ok() ? -1 : 0;
    e.verdict = (r.verdict.ok() ? "a demonstration of failure that did not fail: "
                                : "demonstration of failure, on purpose: ") +
                e.verdict;
  }
  for (const auto& c : r.verdict.criteria)
    if (!c.met) e.problems.push_back({"✘ " + c.text, e.href + "#verdict"});
  for (const auto& a : r.verdict.alarms) e.problems.push_back({"alarm: " + a, e.href + "#verdict"});
  for (const auto& l : r.verdict.unfinished)
    e.problems.push_back({"part not finished: " + l, e.href + "#verdict"});
  for (const auto& u : r.verdict.unmet)
    e.problems.push_back({"model check ✘ " + u.text, e.href + "#claim-" + std::to_string(u.index)});
  return e;
}

// The example files of `dir`, sorted, or only the ones named (in the order named).
std::vector<fs::path> example_files(const std::string& dir, const std::vector<std::string>& only) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw io::InputError("--examples " + dir + ": not a directory");
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".toml") files.push_back(it->path());
  if (ec) throw io::InputError("--examples " + dir + ": " + ec.message());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw io::InputError(dir + ": no example scenarios (*.toml) found");
  if (only.empty()) return files;
  std::vector<fs::path> chosen;
  for (const auto& name : only) {
    const auto it = std::find_if(files.begin(), files.end(),
                                 [&](const fs::path& f) { return f.stem() == name; });
    if (it == files.end()) {
      std::string known;
      for (const auto& f : files) known += (known.empty() ? "" : ", ") + f.stem().string();
      throw io::InputError("demo: no example '" + name + "' in " + dir + " (known: " + known +
                           ")");
    }
    if (std::find(chosen.begin(), chosen.end(), *it) == chosen.end()) chosen.push_back(*it);
  }
  return chosen;
}

int demo(const std::string& out, const std::string& dir, const std::vector<std::string>& only,
         bool strict) {
  const auto lib = io::MaterialLibrary::load_default();
  // Parse all first: nothing runs on a half-read example set.
  std::vector<io::Scenario> scenarios;
  const auto files = example_files(dir, only);
  for (const auto& f : files) scenarios.push_back(systems::load_scenario(f.string(), lib));
  io::prepare_output_dir(out, "--out", false, {files.begin(), files.end()});

  const std::size_t n = scenarios.size();
  std::vector<io::IndexEntry> entries(n);
  std::vector<char> failed(n, 0);
  std::atomic<std::size_t> done{0};
  io::Progress progress("demo");
  try {
    core::parallel_for(
        n,
        [&](std::size_t i) {
          io::OutputStage stage(fs::path(out) / scenarios[i].name);
          io::RunOutput r;
          {
            io::StreamScope streams(stage);  // channels.csv streams into the stage
            r = systems::run_scenario(scenarios[i]);
          }
          io::write_outputs(r, stage, "../index.html");
          entries[i] = index_entry(scenarios[i], r);
          const bool on_purpose = scenarios[i].demonstrates_failure;
          failed[i] = r.verdict.ok() == on_purpose ? 1 : 0;
          progress.print_above([&] {
            std::cout << "  " << scenarios[i].name << ": " << r.headline << " — "
                      << (on_purpose ? "demonstration of failure: " : "") << r.verdict.line()
                      << std::endl;
          });
          const std::size_t k = ++done;
          progress.update(static_cast<double>(k) / static_cast<double>(n),
                          std::to_string(k) + " of " + std::to_string(n) + " scenarios");
        },
        std::max(1u, std::min(std::thread::hardware_concurrency(), 8u)));
  } catch (const io::InputError&) {  // where the results go cannot take them (a full disk)
    progress.finish();
    throw;
  } catch (const fs::filesystem_error&) {
    progress.finish();
    throw;
  } catch (const std::exception& e) {
    progress.finish();
    throw std::runtime_error(e.what());  // a run that fails is an internal failure (exit 1)
  }
  progress.finish();
  io::write_file_atomic(fs::path(out) / "index.html",
                        io::render_index_html("lathectl demo — example scenarios", entries));
  std::string which, shown;
  std::size_t n_failed = 0, n_shown = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (failed[i]) which += (n_failed++ ? ", " : "") + scenarios[i].name;
    if (scenarios[i].demonstrates_failure && !failed[i])
      shown += (n_shown++ ? ", " : "") + scenarios[i].name;
  }
  std::cout << "demo: " << n << " scenarios, " << n_failed
            << " with unmet acceptance criteria, alarms or unfinished parts"
            << (n_failed ? " (" + which + ")" : "");
  if (n_shown > 0)
    std::cout << "; " << n_shown << " demonstrations of failure, failing as they should ("
              << shown << ")";
  std::cout << " → " << (fs::path(out) / "index.html").string() << "\n";
  return strict && n_failed > 0 ? kStrictFailure : 0;
}

}  // namespace

void add_demo(CLI::App& app, Commands& out) {
  struct Args {
    std::string out = "demo-out", dir = examples_dir();
    std::vector<std::string> only;
    bool strict = false;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "demo", "Run every example scenario and write an index.html linking the reports");
  sub->add_option("--out", a->out, "output directory")->capture_default_str();
  sub->add_option("--examples", a->dir, "directory of example scenarios")->capture_default_str();
  sub->add_option("names", a->only,
                  "run only these examples (file names without .toml; default: all)");
  sub->add_flag("--strict", a->strict,
                "exit 3 when any scenario has an acceptance criterion not met, an alarm or an "
                "unfinished part (the model checks, the seeds' claims, do not count; a "
                "demonstration of failure counts when it does not fail)");
  out.push_back({sub, [a] { return demo(a->out, a->dir, a->only, a->strict); }});
}

}  // namespace lathectl::cli
