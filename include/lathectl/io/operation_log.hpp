#pragma once
// The operation log lathectl_oplog writes on LinuxCNC (operations.json: one row per program line
// with feed moves, the taught references, the operator messages), read for `lathectl report`.
// Every value is checked where it is read: a wrong one is one InputError naming the file, the
// line and the key ("operations.json:12:5: key 'rows[0].limit': expected a number").

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "lathectl/io/json_file.hpp"

namespace lathectl::io {

struct OperationLog {
  struct Operation {
    double line = 0.0, operation = 0.0, limit = 0.0, load_mean = 0.0, load_peak = 0.0,
           feed_min = 0.0, feed_mean = 0.0, time_in_cut_s = 0.0;
    int tool = 0;
    std::string mode, reasons, alarm;
  };
  struct Taught {
    double tool = 0.0, operation = 0.0, reference = 0.0;
    std::string unit;
  };
  struct Message {
    double time_s = 0.0;
    std::string text;
  };
  std::string unit = "N";  // N (force) or W (cutting power)
  std::string program;     // "" when the log does not name it
  double missed_rows = 0.0;
  std::vector<Operation> rows;
  std::vector<Taught> taught;
  std::vector<Message> messages;
};

[[nodiscard]] OperationLog read_operation_log(const JsonFile& f);

// One operation, rows[i] at key `key` ("rows[3]") of `f`, checked.
[[nodiscard]] OperationLog::Operation read_operation(const JsonFile& f, const nlohmann::json& row,
                                                     const std::string& key);

// The log read a chunk at a time (at most kMaxOperationLogBytes): each operation handed to
// `each` as it is read and dropped (the log returned has no rows), so memory does not grow with
// the log. A wrong file is the InputError read_operation_log(JsonFile) reports (a syntax error
// first, then the document's keys, then the first wrong row, then the rest); `each` may then
// have seen the rows before the wrong one.
[[nodiscard]] OperationLog read_operation_log(
    const std::filesystem::path& file,
    const std::function<void(const OperationLog::Operation&)>& each,
    std::size_t chunk = std::size_t{1} << 20);

}  // namespace lathectl::io
