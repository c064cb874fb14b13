// The program read by LinuxCNC's own interpreter: rs274 (linuxcnc-uspace) run on a copy whose
// lines carry their line numbers as marker comments, its canonical commands read back.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "optimize/optimize.hpp"
#include "optimize/text.hpp"

namespace lathectl::optimize {
namespace {

namespace fs = std::filesystem;

// A private temporary directory, removed on scope exit.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "lathectl-optimize.XXXXXX").string();
    if (mkdtemp(t.data()) == nullptr)
      throw std::runtime_error("lathectl optimize: cannot create a temporary directory");
    path = t;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// The interpreter's complaint as one line: "LABEL:LINE: rs274: MESSAGE".
std::string interpreter_error(const std::string& err, const std::string& label) {
  std::vector<std::string> lines;
  std::istringstream in(err);
  for (std::string l; std::getline(in, l);)
    if (!l.empty() && l != "executing") lines.push_back(l);
  int line = 0;
  std::string msg;
  const std::string key = "(" + io::canon_line_marker(0).substr(0, 14);  // "(lathectl-line "
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const auto at = lines[i].find(key);
    if (at != std::string::npos) {
      line = std::atoi(lines[i].c_str() + at + key.size());
      continue;
    }
    if (msg.empty()) msg = lines[i];
  }
  if (line == 0) {  // o-word errors name the line themselves
    const auto at = msg.find("line: ");
    if (at != std::string::npos) line = std::atoi(msg.c_str() + at + 6);
  }
  if (msg.empty()) msg = "the interpreter stopped without a message";
  return io::located(label, line, 0, "LinuxCNC's interpreter (rs274) rejects the program: " + msg);
}

}  // namespace

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

io::CanonProgram interpret(const std::vector<std::string>& lines, const std::string& label,
                           const Options& opt) {
  TempDir tmp;
  {
    std::ofstream f(tmp.path / "program.ngc");
    for (const auto& l : marked_lines(lines, opt.spindle_rpm)) f << l << '\n';
    std::ofstream v(tmp.path / "program.var");
  }
  const fs::path ini = opt.ini;
  const fs::path tbl = ini.parent_path() / "lathectl-lathe.tbl";
  // HOME: LinuxCNC 2.9's standalone interpreter creates its tool table as a shared map at
  // $HOME/.tool.mmap, truncating the file (tooldata_mmap.cc, O_TRUNC), before it reads its
  // options — the file a LinuxCNC running as the same user has mapped (io, milltask, halui). That
  // session's tool table becomes rs274's, and its task process (milltask) may die of SIGBUS in
  // the middle of a part, with nothing in the kernel log: 3 runs of rs274 beside a session did
  // it here (the "stalls" of the LinuxCNC tests). Fixed upstream after 2.9.10 (LinuxCNC pull
  // request 4385: sai gets a private file); Debian 12 ships 2.9.0~pre1. Here it gets its own.
  std::string cmd = "HOME=" + shell_quote(tmp.path.string()) + " " + shell_quote(opt.rs274) + " -g";
  if (!opt.ini.empty())
    cmd += " -i " + shell_quote(ini.string()) + " -t " + shell_quote(tbl.string());
  cmd += " -v " + shell_quote((tmp.path / "program.var").string()) + " " +
         shell_quote((tmp.path / "program.ngc").string()) + " " +
         shell_quote((tmp.path / "canon.txt").string()) + " </dev/null 2>" +
         shell_quote((tmp.path / "err.txt").string()) + " >/dev/null";
  const int rc = std::system(cmd.c_str());
  const std::string err = read_text(tmp.path / "err.txt");
  if (rc != 0 && !fs::exists(tmp.path / "canon.txt"))
    throw io::InputError(label + ": cannot run LinuxCNC's interpreter '" + opt.rs274 +
                         "' (linuxcnc-uspace; --rs274 PATH)");
  if (rc != 0) throw io::InputError(interpreter_error(err, label));
  return io::parse_canon(read_text(tmp.path / "canon.txt"), label, opt.start_x_mm, opt.start_z_mm);
}

Program read_program(const std::string& path, const Options& opt) {
  std::istringstream f(io::read_input_file(path, "an NC program", io::kMaxProgramBytes));
  Program p;
  p.file = path;
  for (std::string l; std::getline(f, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    p.lines.push_back(l);
  }
  p.canon = interpret(p.lines, path, opt);
  bool feed = false;
  for (const auto& m : p.canon.moves) feed = feed || m.kind != io::CanonMove::Kind::Traverse;
  if (!feed) throw io::InputError(path + ": the program has no feed moves (nothing to optimise)");
  return p;
}

}  // namespace lathectl::optimize
