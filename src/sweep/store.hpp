#pragma once
// The results store DIR/sweep.sqlite (SQLite 3, WAL): the cases, filled in one transaction before
// any runs, and one results row per finished case, each recorded by one INSERT OR IGNORE in its
// own transaction, so that a kill at any moment loses no finished case and records none twice.
// The Dask driver (python/lathectl/sweep_dask.py) writes the same rows (docs/sweep.md).

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sweep/cases.hpp"

struct sqlite3;

namespace lathectl::sweep {

struct Result {
  std::int64_t case_id = 0;
  std::string status;  // "ok" or "error"
  std::string message;
  double elapsed_s = 0.0;
  std::optional<std::string> summary;  // summary.json's text (none for an error)
};

class Store {
 public:
  // Opens (or creates) the store; throws io::InputError naming the file.
  explicit Store(const std::filesystem::path& file);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // A new store: `cases` inserted in one transaction. A store that has cases: they must be
  // `cases` exactly (the same spec), else io::InputError naming `spec`.
  void fill_or_check(const std::vector<Case>& cases, const std::string& spec);
  // The cases that have a results row.
  [[nodiscard]] std::set<std::int64_t> done() const;
  // INSERT OR IGNORE, its own transaction; thread-safe. False when the case had a row already.
  bool record(const Result& r);
  // Every results row, by case.
  [[nodiscard]] std::vector<Result> results() const;

 private:
  void exec(const char* sql) const;
  [[noreturn]] void fail(const std::string& what) const;
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
};

}  // namespace lathectl::sweep
