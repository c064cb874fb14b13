// The bounded input reader and the guarded single-file output: what a user may give
// where a file is expected, and where a report may go.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"

namespace fs = std::filesystem;
using lathectl::io::InputError;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("lathectl-input-file-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d / name;
}

std::string message_of(auto&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(InputFile, ReadsARegularFileWhole) {
  const auto p = scratch("ok.toml");
  std::ofstream(p) << "system = \"A\"\n";
  EXPECT_EQ(lathectl::io::read_input_file(p, "a scenario", 1024), "system = \"A\"\n");
}

TEST(InputFile, RefusesDevicesBeforeReading) {
  // /dev/zero would be read forever, /dev/urandom until memory ran out.
  for (const char* dev : {"/dev/zero", "/dev/urandom", "/dev/null"})
    EXPECT_EQ(message_of([&] { (void)lathectl::io::read_input_file(dev, "a scenario", 1024); }),
              std::string(dev) + ": is a character device, expected a scenario");
}

TEST(InputFile, RefusesAFifoWithoutWaitingForAWriter) {
  const auto p = scratch("fifo");
  fs::remove(p);
  ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
  EXPECT_EQ(message_of([&] { (void)lathectl::io::read_input_file(p, "a log", 1024); }),
            p.string() + ": is a FIFO (named pipe), expected a log");
}

TEST(InputFile, RefusesDirectoriesMissingAndOversizedFiles) {
  EXPECT_EQ(message_of([&] { (void)lathectl::io::read_input_file(fs::temp_directory_path(), "x", 1); }),
            fs::temp_directory_path().string() + ": is a directory, expected x");
  EXPECT_EQ(message_of([&] { (void)lathectl::io::read_input_file(scratch("absent"), "x", 1); }),
            scratch("absent").string() + ": no such file (expected x)");
  const auto big = scratch("big.toml");
  std::ofstream(big) << std::string(3 << 20, '#');
  EXPECT_EQ(message_of([&] { (void)lathectl::io::read_input_file(big, "a TOML file", 2 << 20); }),
            big.string() + ": 3 MiB, more than the 2 MiB a TOML file may have");
}

TEST(OutputFile, NeverReplacesADeviceTheInputOrAUsersFile) {
  const auto log = scratch("log.json");
  std::ofstream(log) << "{}";
  EXPECT_NE(message_of([&] { lathectl::io::check_output_file("/dev/null", "--out", {log}); })
                .find("not a regular file"),
            std::string::npos);
  EXPECT_NE(message_of([&] { lathectl::io::check_output_file(log, "--out", {log}); })
                .find("is the input"),
            std::string::npos);
  const auto notes = scratch("notes.html");
  std::ofstream(notes) << "<html>my notes</html>";
  EXPECT_NE(message_of([&] { lathectl::io::write_output_file(notes, "x", "--out", {log}); })
                .find("not a page lathectl wrote"),
            std::string::npos);
  std::ifstream in(notes);
  std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "<html>my notes</html>");
}

TEST(OutputFile, ReplacesItsOwnPage) {
  const auto page = scratch("page.html");
  fs::remove(page);
  // (appended, not +: GCC 12's false -Warray-bounds on std::string + literal, bug 105329)
  std::string v1 = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  v1.append(lathectl::io::kGeneratorMeta).append("\n1");
  lathectl::io::write_output_file(page, v1, "--out", {});
  std::string v2 = v1;
  v2.push_back('2');
  lathectl::io::write_output_file(page, v2, "--out", {});
  std::ifstream in(page);
  std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(got, v2);
}

TEST(Progress, GivesTheTimeLeftOnceItCanTell) {
  lathectl::io::Progress p("run x", lathectl::io::Progress::Mode::Off);
  EXPECT_EQ(p.text(12.0), "run x:   0 %, 12 s");
  lathectl::io::Progress q("run x", lathectl::io::Progress::Mode::Plain);
  q.update(0.25, "simulation 1");  // within the first interval: nothing printed
  EXPECT_EQ(q.text(12.0), "run x:  25 % (simulation 1), 12 s, about 36 s left");
  EXPECT_EQ(q.text(400.0), "run x:  25 % (simulation 1), 6 min 40 s, about 20 min 00 s left");
  q.finish();
}
