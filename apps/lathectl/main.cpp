// lathectl — command-line front end: run scenarios, validate them, run the demo, stability lobes,
// the papers' design calculators, the generated reference and the reason codes. One file per
// command (run.cpp, check.cpp, demo.cpp, lobes.cpp, design*.cpp, reference.cpp, reasons.cpp);
// cli.hpp says what they share, program.cpp parses the command line and runs the command chosen.
// Exit codes: 0 success, 1 internal failure, 2 bad input (one clear message), 3 `--strict` and a
// claim not met, an alarm raised or a part not finished.

#include "cli.hpp"

int main(int argc, char** argv) { return lathectl::cli::run_program(argc, argv); }
