#include "app/output_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <system_error>

#include "core/types.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

constexpr const char* kLockName = ".rpfem.lock";

// The files a run writes into its folder, and their temporaries.
const std::vector<std::string>& run_files() {
  static const std::vector<std::string> names{
      "result.h5",      "result.xdmf",         "history.csv",      "summary.json",    "events.csv",
      "result.h5.partial", "result.h5.spare", "result.h5.previous", "result.xdmf.tmp", "history.csv.tmp",
      "summary.json.tmp", "events.csv.tmp"};
  return names;
}

// What the commands write beside the runs' files: a pool's per-run log
// and exit code, the suite's, sweeps' and calibrations' tables and JSON,
// the report; and the folders of the report's figures and the Slurm
// engine.
const std::vector<std::string>& command_files() {
  static const std::vector<std::string> names{
      "run.log",         "exit_code",    "exit_code.tmp",   "suite.json",      "verification.json", "report.html",
      "report.md",       "sweep.csv",    "sweep.h5",        "sweep.json",        "evaluations.csv",
      "calibration.json"};
  return names;
}
const std::vector<std::string>& command_folders() {
  static const std::vector<std::string> names{"report_files", "slurm"};
  return names;
}

struct HeldLock {
  std::string path;  // the lock file's
  int fd;
};
std::vector<HeldLock>& held() {
  static std::vector<HeldLock> locks;
  return locks;
}

// Removed while still locked, so that a process that opened it before
// sees it gone after taking the lock (and takes a new one).
void release(const HeldLock& h) {
  ::unlink(h.path.c_str());
  ::close(h.fd);
}
void release_all() {
  for (const auto& h : held()) release(h);
  held().clear();
}

std::string lock_path(const std::string& dir) {
  std::error_code ec;
  const fs::path canonical = fs::canonical(dir, ec);
  return ((ec ? fs::absolute(dir) : canonical) / kLockName).string();
}

// The pid a lock file holds ("" while its owner has not written it yet).
std::string pid_in(int fd) {
  char buf[32] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string s(buf, n > 0 ? static_cast<std::size_t>(n) : 0);
  s.erase(std::remove_if(s.begin(), s.end(), [](char c) { return c < '0' || c > '9'; }), s.end());
  return s;
}

void lock(const std::string& dir, const std::string& option) {
  const std::string path = lock_path(dir);
  for (const auto& h : held())
    if (h.path == path) return;
  const std::string where = option + " '" + dir + "': ";
  for (int attempt = 0; attempt < 40; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      throw InputError(where + "cannot create its lock file " + kLockName + ": " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const std::string pid = pid_in(fd);
      ::close(fd);
      if (err != EWOULDBLOCK) {
        // A file system without locks: the folder is used unguarded.
        std::fprintf(stderr, "rpfem: warning: %scannot be locked (%s); another run into it is not detected\n",
                     where.c_str(), std::strerror(err));
        return;
      }
      if (pid.empty() && attempt + 1 < 40) {  // its owner is writing its pid
        ::usleep(25000);
        continue;
      }
      throw InputError(where + "in use by another rpfem process (pid " + (pid.empty() ? "unknown" : pid) +
                       ", " + kLockName + "); expected a folder no running rpfem writes into");
    }
    // Its last owner may have removed it between our open and our lock.
    struct stat mine {}, now {};
    if (::fstat(fd, &mine) != 0 || ::stat(path.c_str(), &now) != 0 || mine.st_ino != now.st_ino ||
        mine.st_dev != now.st_dev) {
      ::close(fd);
      continue;
    }
    const std::string text = std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
      const int err = errno;
      ::close(fd);
      throw InputError(where + "cannot write its lock file " + kLockName + ": " + std::strerror(err));
    }
    static const bool at_exit = (std::atexit(release_all), true);
    (void)at_exit;
    held().push_back({path, fd});
    return;
  }
  throw InputError(where + "its lock file " + kLockName + " kept changing; expected a folder no running rpfem writes into");
}

void unlock(const std::string& dir) {
  const std::string path = lock_path(dir);
  auto& locks = held();
  const auto it = std::find_if(locks.begin(), locks.end(), [&](const HeldLock& h) { return h.path == path; });
  if (it == locks.end()) return;
  release(*it);
  locks.erase(it);
}

// Clears folder d (clear(d)) while holding its lock (InputError if another
// rpfem process holds it; `option` names it), then removes d if nothing is
// left in it.
template <class Clear>
void clear_and_remove(const fs::path& d, const std::string& option, Clear clear) {
  make_output_folder(d.string(), option);
  clear(d);
  unlock(d.string());
  std::error_code ec;
  fs::remove(d, ec);  // only if nothing else is left in it
}

// The variant a run folder's summary.json names ("" if none or no summary).
std::string summary_variant(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  if (!in) return "";
  std::ostringstream os;
  os << in.rdbuf();
  const std::string text = os.str();
  static const std::regex key("\"variant\"\\s*:\\s*\"([^\"]*)\"");
  std::string last;
  for (std::sregex_iterator it(text.begin(), text.end(), key), end; it != end; ++it) last = (*it)[1];
  return last;
}

}  // namespace

void forget_inherited_output_folders() {
  for (const auto& h : held()) ::close(h.fd);
  held().clear();
}

void release_output_folders() { release_all(); }

void make_output_folder(const std::string& dir, const std::string& option) {
  if (dir.empty()) throw InputError(option + ": expected a folder name, got an empty one");
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(option + " '" + dir + "': a file is there; expected a folder (or a name not yet used)");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(option + " '" + dir + "': cannot create the output folder: " + ec.message());
  if (!fs::is_directory(dir, ec)) throw InputError(option + " '" + dir + "': not a folder after creating it");
  lock(dir, option);
}

void claim_output_folder(const std::string& dir, ExistingOutput existing, bool resume_hint,
                         const std::string& option) {
  make_output_folder(dir, option);
  if (existing == ExistingOutput::Keep) return;
  std::error_code ec;
  std::vector<std::string> held_names;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().filename() != kLockName) held_names.push_back(entry.path().filename().string());
  if (held_names.empty()) return;
  if (existing == ExistingOutput::Replace) {
    remove_previous_outputs(dir);
    return;
  }
  std::sort(held_names.begin(), held_names.end());
  std::string listed;
  for (std::size_t i = 0; i < held_names.size() && i < 3; ++i) listed += (i ? ", " : "") + held_names[i];
  if (held_names.size() > 3) listed += ", ... (" + std::to_string(held_names.size()) + " entries)";
  throw InputError(option + " '" + dir + "': not empty (" + listed +
                   "); expected a new or empty folder, or --force to replace what an earlier rpfem command wrote "
                   "there" +
                   (resume_hint ? " (--resume: keep its finished runs)" : ""));
}

void remove_previous_outputs(const std::string& dir) {
  std::error_code ec;
  // Deepest folders first, so that a folder emptied below is removed too.
  std::vector<fs::path> folders;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && !it->is_symlink(ec)) folders.push_back(it->path());
  std::sort(folders.begin(), folders.end(), [](const fs::path& a, const fs::path& b) {
    return std::distance(a.begin(), a.end()) > std::distance(b.begin(), b.end());
  });
  const auto clear = [&](const fs::path& d) {
    remove_run_results(d.string());
    for (const auto& name : command_files()) {
      fs::remove(d / name, ec);
      fs::remove(d / (name + ".tmp"), ec);
    }
    for (const auto& name : command_folders())
      if (fs::is_directory(d / name, ec) && !fs::is_symlink(d / name, ec)) fs::remove_all(d / name, ec);
  };
  for (const auto& d : folders)
    if (fs::exists(d, ec)) clear_and_remove(d, "folder", clear);  // (not inside report_files/, slurm/, removed whole)
  clear(dir);
}

void remove_run_results(const std::string& dir) {
  std::error_code ec;
  for (const auto& name : run_files()) fs::remove(fs::path(dir) / name, ec);
  // meshio's files: result_meshio.xdmf and one per remeshed segment
  // (result_meshio_NNNNNN.xdmf), and their temporaries.
  std::vector<fs::path> meshio;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("result_meshio", 0) == 0 &&
        (name.ends_with(".xdmf") || name.ends_with(".xdmf.tmp")))
      meshio.push_back(entry.path());
  }
  for (const auto& p : meshio) fs::remove(p, ec);
}

void remove_stale_variant_runs(const std::string& parent, const std::vector<std::string>& keep) {
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) return;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory(ec) || std::find(keep.begin(), keep.end(), name) != keep.end()) continue;
    if (summary_variant(entry.path()) == name) stale.push_back(entry.path());
  }
  for (const auto& d : stale)
    clear_and_remove(d, "variant folder", [](const fs::path& f) {
      remove_run_results(f.string());
      std::error_code e;
      fs::remove(f / "run.log", e);
    });
}

}  // namespace rpfem
