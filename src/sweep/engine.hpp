#pragma once
// `lathectl sweep`'s engines and outputs (docs/sweep.md): the local engine runs the cases
// without a result on this machine's cores; the Dask engine hands DIR to the Python driver
// lathectl.sweep_dask, which runs them on a Dask cluster and records them in the same store.
// Either way results.csv and report.html are then written from the store.

#include <filesystem>
#include <string>
#include <vector>

#include "lathectl/io/materials.hpp"
#include "lathectl/io/report.hpp"
#include "sweep/cases.hpp"
#include "sweep/spec.hpp"
#include "sweep/store.hpp"

namespace lathectl::sweep {

// Runs one case as every engine does: its text read under case_label(base_dir, id)
// (systems::parse_scenario) and run (systems::run_scenario) for its summary alone
// (io::SummaryOnly: no report built). A failure (bad input, divergence) is an "error" result
// with its message on one line, never an exception.
Result run_case(const Case& c, const io::MaterialLibrary& lib);

// The local engine: the cases without a row in `store`, on `workers` threads (0: every core),
// each recorded as it finishes; progress and time left on stderr. Returns the number run.
std::size_t run_local(const std::vector<Case>& cases, Store& store, unsigned workers,
                      const io::MaterialLibrary& lib);

// The directory holding the Dask driver lathectl/sweep_dask.py beside the program (the build
// tree's python/, or the installed package; $LATHECTL_PYTHON_DIR first). Throws io::InputError
// when it is missing or `scheduler` is not tcp://HOST:PORT. Called before anything is written.
std::string find_dask_driver(const std::string& scheduler);
// The Dask engine: `/usr/bin/python3 -m lathectl.sweep_dask --scheduler ADDRESS DIR` with `pydir`
// on PYTHONPATH, waited for; std::runtime_error when the driver fails.
void run_dask(const std::string& pydir, const std::string& scheduler,
              const std::filesystem::path& dir);

// DIR/cases.csv: `case`, then the varied keys' values (before any runs).
void write_cases_csv(const std::filesystem::path& dir, const Spec& spec,
                     const std::vector<std::vector<Value>>& values);

// The metrics of a summary.json text: the numeric scalars under "metrics", named by their path
// below it ("vibration_amplitude_um.with"), in the summary's order.
std::vector<std::pair<std::string, double>> metrics_of(const std::string& summary_json);

// DIR/results.csv and DIR/report.html from the store's rows (each written atomically).
void write_results(const std::filesystem::path& dir, const Spec& spec,
                   const std::vector<std::vector<Value>>& values,
                   const std::vector<Result>& results);

// [report]'s machine file read as `lathectl lobes` reads it, before any case runs; an error is
// an io::InputError at the spec's `lobes` line. Nothing without [report].
void check_lobes_machine(const Spec& spec);
// [report] (lobes_overlay.cpp): the lobes' boundary over rep's heat maps (their axes the speed
// and depth keys), and each grid point's simulated verdict (`chatter`: the chatter metric per
// grid point, NaN: none) set against it: the agreement in rep's metrics, the disagreements as a
// table.
void lobes_overlay(const Spec& spec, const std::vector<double>& chatter, io::Report& rep);

// The report of a sweep (report.cpp): lines for one grid key, heat maps for two and more, the
// failed cases listed.
std::string report_html(const Spec& spec, const std::vector<std::vector<Value>>& values,
                        const std::vector<Result>& results,
                        const std::vector<std::string>& metrics);

}  // namespace lathectl::sweep
