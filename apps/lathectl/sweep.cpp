// `lathectl sweep SPEC --out DIR [--workers N] [--scheduler tcp://HOST:PORT]`: many runs of one
// scenario (docs/sweep.md). The spec is read and every value checked before anything is written;
// the cases go into DIR/sweep.sqlite and DIR/cases.csv, run locally or on a Dask cluster, and
// DIR/results.csv and DIR/report.html are written from the store. A rerun on the same DIR runs
// only the cases without a result.
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <string>

#include "cli.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/scenario.hpp"
#include "sweep/engine.hpp"

namespace fs = std::filesystem;

namespace lathectl::cli {
namespace {

struct SweepArgs {
  std::string spec, out;
  unsigned workers = 0;
  std::string scheduler;
};

int sweep(const SweepArgs& a) {
  const auto spec = sweep::read_spec(a.spec);
  sweep::check_lobes_machine(spec);
  const std::string driver = a.scheduler.empty() ? "" : sweep::find_dask_driver(a.scheduler);
  const std::string text = sweep::read_scenario(spec);
  const auto values = sweep::draw_values(spec);
  const auto lib = io::MaterialLibrary::load_default();
  sweep::check_values(spec, text, values, lib);  // before anything is written
  const auto cases = sweep::make_cases(spec, text, values);
  const fs::path dir(a.out);
  io::prepare_output_dir(dir, "--out", false, {a.spec, spec.scenario});
  fs::create_directories(dir);
  sweep::Store store(dir / "sweep.sqlite");
  store.fill_or_check(cases, a.spec);
  sweep::write_cases_csv(dir, spec, values);
  const std::size_t before = store.done().size();
  if (a.scheduler.empty())
    sweep::run_local(cases, store, a.workers, lib);
  else
    sweep::run_dask(driver, a.scheduler, dir);
  const auto results = store.results();
  sweep::write_results(dir, spec, values, results);
  std::size_t ok = 0;
  std::set<std::string> seen;  // the metrics the cases have, for [output] metrics' names
  for (const auto& r : results) {
    ok += r.status == "ok";
    if (r.summary && !spec.metrics.empty())
      for (const auto& [name, v] : sweep::metrics_of(*r.summary)) seen.insert(name);
  }
  for (const auto& m : spec.metrics)
    if (ok && !seen.contains(m))
      std::cerr << "warning: " << io::error_line(a.spec + ": [output] metric '" + m)
                << "' is a number in no case's summary.json (its column is empty)\n";
  std::cout << "sweep " << a.spec << ": " << cases.size() << " cases, " << ok << " ok, "
            << results.size() - ok << " failed (" << results.size() - before << " run now, "
            << before << " done before)\n  → " << (dir / "report.html").string() << "\n";
  if (results.size() != cases.size())
    throw std::runtime_error("sweep " + a.spec + ": " +
                             std::to_string(cases.size() - results.size()) +
                             " cases have no result; rerun the same command");
  return 0;
}

}  // namespace

void add_sweep(CLI::App& app, Commands& out) {
  auto a = std::make_shared<SweepArgs>();
  auto* sub = app.add_subcommand(
      "sweep", "Run many cases of one scenario (a grid and random samples of its keys) and "
               "write cases.csv, results.csv, report.html; a rerun runs only the cases not done");
  sub->add_option("spec", a->spec, "sweep spec (TOML: scenario, [grid], [random], [output])")
      ->required();
  sub->add_option("--out", a->out, "output directory (holds sweep.sqlite, the results store)")
      ->required();
  sub->add_option("--workers", a->workers, "cases run at once (0: every core)")
      ->capture_default_str();
  sub->add_option("--scheduler", a->scheduler,
                  "run the cases on a Dask cluster: its scheduler's address, tcp://HOST:PORT");
  sub->footer("Spec and outputs: " + doc("sweep.md") + ".");
  out.push_back({sub, [a] { return sweep(*a); }});
}

}  // namespace lathectl::cli
