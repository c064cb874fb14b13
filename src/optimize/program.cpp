// The program read by LinuxCNC's own interpreter: rs274 (linuxcnc-uspace) run on a copy whose
// lines carry their line numbers as marker comments, its canonical commands read back.
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <optional>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <thread>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/linuxcnc_ini.hpp"
#include "optimize/optimize.hpp"
#include "optimize/path.hpp"
#include "optimize/text.hpp"
#include "optimize/tools.hpp"

namespace lathectl::optimize {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kTempPrefix = "lathectl-optimize.";

// Temporary directories of earlier runs that were killed outright (SIGKILL leaves no chance to
// clean up): "lathectl-optimize.<pid>.XXXXXX" whose process no longer exists.
void remove_stale_temp_dirs(const fs::path& base) {
  std::error_code ec;
  for (fs::directory_iterator it(base, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(kTempPrefix, 0) != 0) continue;
    const long pid = std::atol(name.c_str() + kTempPrefix.size());
    struct stat st {};
    if (pid <= 0 || ::stat(it->path().c_str(), &st) != 0 || st.st_uid != ::getuid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) {
      std::error_code rm;
      fs::remove_all(it->path(), rm);
    }
  }
}

// A private temporary directory, removed on scope exit; its name carries this process's id, so
// that a later run removes it if this one is killed outright.
struct TempDir {
  fs::path path;
  TempDir() {
    const fs::path base = fs::temp_directory_path();
    remove_stale_temp_dirs(base);
    std::string t = (base / (std::string(kTempPrefix) + std::to_string(::getpid()) + ".XXXXXX"))
                        .string();
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

// SIGINT, SIGTERM and SIGHUP are noted while the interpreter runs, so that its process group and
// the temporary directory are gone before lathectl dies of the signal.
volatile std::sig_atomic_t g_signal = 0;
extern "C" void note_signal(int sig) { g_signal = sig; }
struct SignalGuard {
  static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction old[3] {};
  SignalGuard() {
    g_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = note_signal;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &sa, &old[i]);
  }
  ~SignalGuard() { restore(); }
  void restore() {
    for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &old[i], nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;
};

std::uintmax_t bytes_of(const fs::path& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 ? static_cast<std::uintmax_t>(st.st_size) : 0;
}

// Runs rs274 in a process group of its own, which dies with lathectl (PR_SET_PDEATHSIG) and is
// killed when it runs longer than opt.interp_timeout_s or writes more than
// opt.interp_output_max_bytes (an endless o-word loop does both). Returns its exit status.
int run_interpreter(const TempDir& tmp, const std::vector<std::string>& args, const Options& opt,
                    const std::string& label) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::string home = "HOME=" + tmp.path.string();
  const std::string err = (tmp.path / "err.txt").string();
  const fs::path canon = tmp.path / "canon.txt";
  SignalGuard guard;
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("lathectl optimize: cannot start a process (fork)");
  if (pid == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // lathectl died before the line above
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open("/dev/null", O_WRONLY);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (in < 0 || out < 0 || e < 0) ::_exit(127);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(e, 2);
    ::putenv(home.data());
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: whichever runs first
  const auto start = std::chrono::steady_clock::now();
  std::string stopped;
  int status = 0;
  for (;;) {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) break;
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int sig = g_signal;
    if (sig != 0 || t > opt.interp_timeout_s || bytes_of(canon) > opt.interp_output_max_bytes) {
      ::kill(-pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      if (sig != 0) {  // die of the signal, as without the guard, once the directory is gone
        std::error_code ec;
        fs::remove_all(tmp.path, ec);
        guard.restore();
        ::raise(sig);
      }
      char buf[160];
      if (t > opt.interp_timeout_s)
        std::snprintf(buf, sizeof buf, "did not finish within %g s", opt.interp_timeout_s);
      else
        std::snprintf(buf, sizeof buf, "wrote more than %g MB of moves",
                      static_cast<double>(opt.interp_output_max_bytes) / 1e6);
      throw io::InputError(label + ": LinuxCNC's interpreter (rs274) " + buf +
                           " and was stopped: an endless loop (o-word while/do/repeat)? "
                           "(--interp-timeout S)");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

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

void check_soft_limits(const Program& p, const std::string& ini_file) {
  const auto mc = io::lathe_machine(io::parse_linuxcnc_ini(read_text(ini_file), ini_file));
  struct Axis {
    const char* name;
    std::optional<double> lo, hi;
  };
  const Axis ax[2] = {{"AXIS_X", mc.x_min, mc.x_max}, {"AXIS_Z", mc.z_min, mc.z_max}};
  constexpr double kTol = 1e-4;  // mm: the interpreter's 4 decimals
  for (const auto& m : p.canon.moves) {
    // An arc's extent lies between its ends: sampled finely enough for 1e-4 mm at any radius
    // a lathe turns (r·(1 − cos(π/n)) with n = 2048).
    const int n = m.kind == io::CanonMove::Kind::Arc ? 2048 : 1;
    for (int k = 1; k <= n; ++k) {
      const auto [x, z] = point_at(m, static_cast<double>(k) / n);
      const double pos[2] = {x + m.offset_x, z + m.offset_z};
      for (int a = 0; a < 2; ++a) {
        const bool low = ax[a].lo && pos[a] < *ax[a].lo - kTol;
        const bool high = ax[a].hi && pos[a] > *ax[a].hi + kTol;
        if (!low && !high) continue;
        char buf[240];
        const double u = mc.unit_mm;  // the INI's numbers in its own units
        std::snprintf(buf, sizeof buf,
                      "the move reaches machine %c %.4f%s, beyond the soft limit [%s] %s = %g of "
                      "%s: LinuxCNC refuses the program",
                      a == 0 ? 'X' : 'Z', pos[a] / u, u > 1.0 ? " in" : "", ax[a].name,
                      low ? "MIN_LIMIT" : "MAX_LIMIT", (low ? *ax[a].lo : *ax[a].hi) / u,
                      ini_file.c_str());
        throw io::InputError(io::located(p.file, m.line, 0, buf));
      }
    }
  }
}

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

namespace {
// LinuxCNC's tool table, read whole on the checked path; one without a tool is refused too.
std::string read_tool_table_file(const fs::path& tbl) {
  std::string text =
      io::read_input_file(tbl, "a LinuxCNC tool table (--tool-table)", io::kMaxTomlBytes);
  if (read_tool_table(text, tbl.string()).empty())
    throw io::InputError(tbl.string() + ": " + (text.empty() ? "empty" : "no tool in it") +
                         ", expected a LinuxCNC tool table (--tool-table): T, P, D, ... words "
                         "per tool");
  return text;
}

}  // namespace

// The tool table with its lengths (D and the X Y Z U V W offsets) times `factor`; the angles (I,
// J, A, B, C), numbers and orientation as they were, comments kept.
std::string tool_table_scaled(const std::string& text, double factor) {
  std::istringstream in(text);
  std::string out;
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    const auto semi = l.find(';');
    if (semi == 0) {
      out += l + "\n";
      continue;
    }
    std::istringstream ws(l.substr(0, semi));
    std::string line;
    for (std::string w; ws >> w;) {
      const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(w[0])));
      if (std::string_view("DXYZUVW").find(c) != std::string_view::npos && w.size() > 1) {
        char* end = nullptr;
        const double v = std::strtod(w.c_str() + 1, &end);
        if (end != w.c_str() + 1 && *end == '\0') {
          char b[40];
          std::snprintf(b, sizeof b, "%c%.10g", c, v * factor);
          w = b;
        }
      }
      line += (line.empty() ? "" : " ") + w;
    }
    if (semi != std::string::npos) line += " " + l.substr(semi);
    out += line + "\n";
  }
  return out;
}

std::string machine_tool_table(const std::string& ini_file, const io::LatheMachine& mc) {
  if (mc.tool_table.empty())
    throw io::InputError(ini_file + ": [EMCIO]TOOL_TABLE missing: the machine's tool table "
                                    "(or --tool-table TABLE)");
  const fs::path t(mc.tool_table);
  return (t.is_absolute() ? t : fs::path(ini_file).parent_path() / t).string();
}

MachineStart machine_start(const io::LatheMachine& mc, const std::string& ini_file,
                           const systems::e_adaptive::Settings& e, const Options& opt) {
  const auto& blank = e.rig.stock.blank_diameter_mm;
  double r_max = 0.0, z_lo = 0.0;
  for (const auto& b : blank) r_max = std::max(r_max, 0.5 * b.value);
  if (!blank.empty()) z_lo = blank.front().at_mm;
  r_max += e.rig.stock.eccentricity_mm;
  const double nose = 2.0 * e.rig.cutting.nose_radius_mm;
  // Machine z = z_origin − stock z: the face (stock z_lo) at machine z_origin − z_lo.
  const double face_z = opt.z_origin_mm - z_lo;
  MachineStart s{mc.home_x, mc.home_z, true, {}};
  if (mc.home_x >= r_max + nose || mc.home_z >= face_z + nose) return s;
  const auto key = [](const std::string& k, int line) {
    return line == 0 ? k + " absent (0)" : k + " (line " + std::to_string(line) + ")";
  };
  char buf[400];
  const double u = mc.unit_mm;
  std::snprintf(buf, sizeof buf,
                "%s: %s, %s: LinuxCNC homes the tool at X%g Z%g %s, in the blank (radius up to "
                "%.4g mm, face at machine Z%.4g mm; the simulated lathe has no work offsets); it "
                "starts at X%g Z%g mm as without --ini",
                ini_file.c_str(), key(mc.home_x_key, mc.home_x_line).c_str(),
                key(mc.home_z_key, mc.home_z_line).c_str(), mc.home_x / u, mc.home_z / u,
                u > 1.0 ? "inch" : "mm", r_max, face_z, opt.start_x_mm, opt.start_z_mm);
  return {opt.start_x_mm, opt.start_z_mm, false, buf};
}

io::CanonProgram interpret(const std::vector<std::string>& lines, const std::string& label,
                           const Options& opt) {
  const fs::path ini = opt.ini;
  io::LatheMachine mc;
  if (!opt.ini.empty()) mc = io::lathe_machine(io::parse_linuxcnc_ini(read_text(ini), opt.ini));
  fs::path tbl = opt.tool_table.empty() ? fs::path(machine_tool_table(opt.ini, mc))
                                        : fs::path(opt.tool_table);
  // The tool table on the checked path, before the temporary directory exists: a FIFO, a device,
  // a directory, a missing or an empty file is one line naming it and --tool-table (LinuxCNC
  // would say "Requested tool 1 not found", or wait for ever on a FIFO). rs274 reads the copy.
  std::string table;
  if (!opt.ini.empty()) table = read_tool_table_file(tbl);
  TempDir tmp;
  {
    std::ofstream f(tmp.path / "program.ngc");
    for (const auto& l : marked_lines(lines, opt.spindle_rpm)) f << l << '\n';
    std::ofstream v(tmp.path / "program.var");
  }
  // LinuxCNC 2.9's standalone interpreter takes the tool table's lengths in inches, whatever the
  // INI's [TRAJ]LINEAR_UNITS (its canon's length unit; milltask converts, rs274 does not): the
  // simulated lathe's T1 D0.8 became a nose of 10.16 mm radius under G41/G42 (a 7 mm entry move
  // "not greater than the tool radius", a gouge at every concave corner), and a Z1 offset
  // 25.4 mm. On a millimetre machine it reads a copy with those lengths in inches.
  if (!opt.ini.empty()) {
    std::ofstream t(tmp.path / "tools.tbl");
    t << (mc.unit_mm == 1.0 ? tool_table_scaled(table, 1.0 / 25.4) : table);
    tbl = tmp.path / "tools.tbl";
  }
  // HOME: LinuxCNC 2.9's standalone interpreter creates its tool table as a shared map at
  // $HOME/.tool.mmap, truncating the file (tooldata_mmap.cc, O_TRUNC), before it reads its
  // options — the file a LinuxCNC running as the same user has mapped (io, milltask, halui). That
  // session's tool table becomes rs274's, and its task process (milltask) may die of SIGBUS in
  // the middle of a part, with nothing in the kernel log: 3 runs of rs274 beside a session did
  // it here (the "stalls" of the LinuxCNC tests). Fixed upstream after 2.9.10 (LinuxCNC pull
  // request 4385: sai gets a private file); Debian 12 ships 2.9.0~pre1. Here it gets its own
  // (run_interpreter).
  std::vector<std::string> args{opt.rs274, "-g"};
  if (!opt.ini.empty()) args.insert(args.end(), {"-i", ini.string(), "-t", tbl.string()});
  args.insert(args.end(), {"-v", (tmp.path / "program.var").string(),
                           (tmp.path / "program.ngc").string(), (tmp.path / "canon.txt").string()});
  const int rc = run_interpreter(tmp, args, opt, label);
  const std::string err = read_text(tmp.path / "err.txt");
  if (rc != 0 && !fs::exists(tmp.path / "canon.txt"))
    throw io::InputError(label + ": cannot run LinuxCNC's interpreter '" + opt.rs274 +
                         "' (linuxcnc-uspace; --rs274 PATH)");
  // rs274 writes its canonical commands even for an empty program (its units, offsets, ...):
  // nothing written is a program that is not rs274 (--rs274 /bin/true), not a program without
  // feed moves.
  if (bytes_of(tmp.path / "canon.txt") == 0)
    throw io::InputError("--rs274 '" + opt.rs274 + "' exited with status " + std::to_string(rc) +
                         " without writing the canonical commands LinuxCNC's interpreter "
                         "writes: it is not LinuxCNC's rs274 (linuxcnc-uspace)");
  if (rc != 0) throw io::InputError(interpreter_error(err, label));
  // The travel to [EMCIO]TOOL_CHANGE_POSITION at each M6 is LinuxCNC's task's, not the
  // interpreter's: rs274 does not print it (io::parse_canon adds it).
  std::optional<io::ToolChangePosition> tool_change;
  if (mc.tool_change_x && mc.tool_change_z)
    tool_change = io::ToolChangePosition{*mc.tool_change_x, *mc.tool_change_z};
  return io::parse_canon(read_text(tmp.path / "canon.txt"), label, opt.start_x_mm, opt.start_z_mm,
                         tool_change);
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
  // Everything after the interpreter holds a few kB a move (segments with their blend arcs,
  // pieces, the rewritten program, blocks.csv): a 10⁶-line program took 1.6 GB.
  if (p.canon.moves.size() > kMaxProgramMoves)
    throw io::InputError(io::located(
        path, p.canon.moves[kMaxProgramMoves].line, 0,
        "the program has " + std::to_string(p.canon.moves.size()) + " moves, more than the " +
            std::to_string(kMaxProgramMoves) +
            " lathectl optimize takes (about 1.6 kB of memory a move); this is the first beyond: "
            "split the program"));
  if (!opt.ini.empty()) check_soft_limits(p, opt.ini);
  bool feed = false;
  for (const auto& m : p.canon.moves) feed = feed || m.kind != io::CanonMove::Kind::Traverse;
  if (!feed) throw io::InputError(path + ": the program has no feed moves (nothing to optimise)");
  return p;
}

}  // namespace lathectl::optimize
