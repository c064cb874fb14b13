// The program's body (main.cpp calls it): the command line parsed, the command chosen run, its
// errors turned into one message and the exit code. The Python module calls it for what it hands
// to a command (its design calculators), so both parse and check the same way.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>

#include "cli.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl_version.hpp"

namespace lathectl::cli {

int run_program(int argc, char** argv) {
  CLI::App app{"lathectl — automatic and adaptive lathe control: simulate, design, deploy"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("lathectl ") + LATHECTL_VERSION + " (commit " +
                                        LATHECTL_GIT_COMMIT + ")");
  // Where the seed, formula and block numbers of the help texts are explained (subcommands
  // inherit the footer; the ones with a page of their own name it).
  app.footer(
      "Exit codes: 0 success; 1 internal failure; 2 bad input (one message naming file, line and "
      "key); 3 with --strict (run, demo): an acceptance criterion not met, an alarm raised or a "
      "part not finished.\n"
      "Seed numbers (000–004), formula numbers such as (23) and block numbers such as \"sensor "
      "4\" refer to the five original documents, explained in " +
      doc("README.md") + ".");

  Commands commands;
  add_run(app, commands);
  add_check(app, commands);
  add_demo(app, commands);
  add_lobes(app, commands);
  add_report(app, commands);
  add_design(app, commands);
  add_reference(app, commands);
  add_compare(app, commands);
  add_optimize(app, commands);
  add_reasons(app, commands);
  add_systems(app, commands);
  add_sweep(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // Every message below is one printable, bounded line (io::error_line): a file's or a flag's
  // text never reaches the terminal raw.
  // A bad command line is bad input like any other: one line naming the command and the flag.
    std::cerr << "error: " << io::error_line(command_line_error(app, e, argc, argv)) << "\n";
    return kBadInput;
  }

  try {
    for (const auto& c : commands)
      if (c.app->parsed()) return c.run();
  } catch (const io::InputError& e) {
    std::cerr << "error: " << io::error_line(e.what()) << "\n";
    return kBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    // Where the results were to go cannot take them (a full disk, a quota, a read-only or vanished
    // directory): the user's to fix, like a bad --out. Nothing half written is left (the output
    // sets are staged and removed on failure).
    std::cerr << "error: " << io::error_line(e.path1().string()) << ": " << e.code().message()
              << (e.code() == std::errc::no_space_on_device
                      ? " (free space on that file system, or choose another --out)"
                      : "")
              << "\n";
    return kBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory: the input asks for more than this machine has "
                 "(lathectl check FILE estimates a run's size)\n";
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << io::error_line(e.what()) << "\n";
    return 1;
  }
  return 1;
}

}  // namespace lathectl::cli
