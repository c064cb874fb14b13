// DIR/sweep.sqlite: the schema of docs/sweep.md, WAL, one transaction per recorded case.
#include "sweep/store.hpp"

#include <sqlite3.h>

#include <memory>

#include "lathectl/io/errors.hpp"

namespace lathectl::sweep {
namespace {

constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS cases(case_id INTEGER PRIMARY KEY, scenario TEXT NOT NULL, "
    "base_dir TEXT NOT NULL, vars TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS results(case_id INTEGER PRIMARY KEY REFERENCES cases(case_id), "
    "status TEXT NOT NULL CHECK(status IN ('ok','error')), message TEXT NOT NULL, "
    "elapsed_s REAL NOT NULL, summary TEXT);";

using Stmt = std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)>;

std::string column_text(sqlite3_stmt* s, int i) {
  const auto* p = sqlite3_column_text(s, i);
  return p ? std::string(reinterpret_cast<const char*>(p),
                         static_cast<std::size_t>(sqlite3_column_bytes(s, i)))
           : std::string();
}

void bind(sqlite3_stmt* s, int i, const std::string& t) {
  sqlite3_bind_text(s, i, t.data(), static_cast<int>(t.size()), SQLITE_TRANSIENT);
}

}  // namespace

Store::Store(const std::filesystem::path& file) : file_(file) {
  if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK)
    fail("cannot open");
  sqlite3_busy_timeout(db_, 30000);  // the Dask driver may be writing
  exec("PRAGMA journal_mode=WAL;");
  exec("PRAGMA synchronous=NORMAL;");  // WAL: a killed process loses no committed transaction
  exec(kSchema);
}

Store::~Store() { sqlite3_close(db_); }

void Store::fail(const std::string& what) const {
  throw io::InputError(file_.string() + ": " + what + " (" +
                       (db_ ? sqlite3_errmsg(db_) : "out of memory") + ")");
}

void Store::exec(const char* sql) const {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string m = err ? err : "?";
    sqlite3_free(err);
    throw io::InputError(file_.string() + ": " + m);
  }
}

void Store::fill_or_check(const std::vector<Case>& cases, const std::string& spec) {
  const std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE;");
  try {
    sqlite3_stmt* raw = nullptr;
    sqlite3_prepare_v2(db_, "SELECT case_id, scenario, base_dir, vars FROM cases ORDER BY case_id",
                       -1, &raw, nullptr);
    Stmt sel(raw, sqlite3_finalize);
    std::size_t n = 0;
    for (; sqlite3_step(sel.get()) == SQLITE_ROW; ++n) {
      const bool same = n < cases.size() && sqlite3_column_int64(sel.get(), 0) == cases[n].id &&
                        column_text(sel.get(), 1) == cases[n].scenario &&
                        column_text(sel.get(), 2) == cases[n].base_dir &&
                        column_text(sel.get(), 3) == cases[n].vars;
      if (!same)
        throw io::InputError(spec + ": " + file_.string() + " holds case " +
                             std::to_string(n) + " of another sweep (another spec, scenario "
                             "or its files' place): use another --out, or remove the directory");
    }
    if (n != 0 && n != cases.size())
      throw io::InputError(spec + ": " + file_.string() + " holds " + std::to_string(n) +
                           " cases, the spec makes " + std::to_string(cases.size()) +
                           ": use another --out, or remove the directory");
    if (n == 0) {
      sqlite3_prepare_v2(db_, "INSERT INTO cases VALUES (?, ?, ?, ?)", -1, &raw, nullptr);
      Stmt ins(raw, sqlite3_finalize);
      for (const auto& c : cases) {
        sqlite3_reset(ins.get());
        sqlite3_bind_int64(ins.get(), 1, c.id);
        bind(ins.get(), 2, c.scenario);
        bind(ins.get(), 3, c.base_dir);
        bind(ins.get(), 4, c.vars);
        if (sqlite3_step(ins.get()) != SQLITE_DONE) fail("cannot write the cases");
      }
    }
    exec("COMMIT;");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK;", nullptr, nullptr, nullptr);
    throw;
  }
}

std::set<std::int64_t> Store::done() const {
  const std::lock_guard lock(mutex_);
  sqlite3_stmt* raw = nullptr;
  sqlite3_prepare_v2(db_, "SELECT case_id FROM results", -1, &raw, nullptr);
  Stmt s(raw, sqlite3_finalize);
  std::set<std::int64_t> ids;
  while (sqlite3_step(s.get()) == SQLITE_ROW) ids.insert(sqlite3_column_int64(s.get(), 0));
  return ids;
}

bool Store::record(const Result& r) {
  const std::lock_guard lock(mutex_);
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db_, "INSERT OR IGNORE INTO results VALUES (?, ?, ?, ?, ?)", -1, &raw,
                         nullptr) != SQLITE_OK)
    fail("cannot record a result");
  Stmt s(raw, sqlite3_finalize);
  sqlite3_bind_int64(s.get(), 1, r.case_id);
  bind(s.get(), 2, r.status);
  bind(s.get(), 3, r.message);
  sqlite3_bind_double(s.get(), 4, r.elapsed_s);
  if (r.summary)
    bind(s.get(), 5, *r.summary);
  else
    sqlite3_bind_null(s.get(), 5);
  if (sqlite3_step(s.get()) != SQLITE_DONE) fail("cannot record case " + std::to_string(r.case_id));
  return sqlite3_changes(db_) == 1;
}

std::vector<Result> Store::results() const {
  const std::lock_guard lock(mutex_);
  sqlite3_stmt* raw = nullptr;
  sqlite3_prepare_v2(db_,
                     "SELECT case_id, status, message, elapsed_s, summary FROM results "
                     "ORDER BY case_id",
                     -1, &raw, nullptr);
  Stmt s(raw, sqlite3_finalize);
  std::vector<Result> out;
  while (sqlite3_step(s.get()) == SQLITE_ROW) {
    Result r{sqlite3_column_int64(s.get(), 0), column_text(s.get(), 1), column_text(s.get(), 2),
             sqlite3_column_double(s.get(), 3), std::nullopt};
    if (sqlite3_column_type(s.get(), 4) != SQLITE_NULL) r.summary = column_text(s.get(), 4);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace lathectl::sweep
