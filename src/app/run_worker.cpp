#include "app/run_worker.hpp"

#include <fcntl.h>
#include <stdio_ext.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <vector>

#include "app/output_folder.hpp"
#include "app/subprocess.hpp"

namespace rpfem {

namespace {

// This process's ends of its workers' sockets. A worker started by one
// pool thread inherits the others' ends and closes them: a worker ends
// when its socket's last parent end is closed.
std::mutex g_sockets_mutex;  // also held over fork(): one fork at a time
std::vector<int> g_sockets;

bool send_all(int fd, const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);  // a worker gone: an error, not SIGPIPE
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k, n -= static_cast<std::size_t>(k);
  }
  return true;
}

bool recv_all(int fd, void* data, std::size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t k = ::recv(fd, p, n, 0);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k, n -= static_cast<std::size_t>(k);
  }
  return true;
}

// The worker's life: a job index in, the job's exit code out, until this
// process closes the socket.
[[noreturn]] void serve(int fd, const std::function<std::string(std::size_t)>& log,
                        const std::function<int(std::size_t)>& job) {
  const int parent_stderr = ::dup(STDERR_FILENO);  // where a log that cannot be opened is said
  for (std::uint64_t i; recv_all(fd, &i, sizeof i);) {
    std::int32_t rc = 2;
    const std::string path = log(i);
    const int out = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out < 0) {
      dprintf(parent_stderr, "rpfem: error: cannot write %s: %s\n", path.c_str(), std::strerror(errno));
    } else {
      ::dup2(out, STDOUT_FILENO);
      ::dup2(out, STDERR_FILENO);
      ::close(out);
      rc = report_errors([&] { return job(i); });
      std::fflush(stdout);
      std::fflush(stderr);
      // As a run's process would at its end: the run's folder released.
      release_output_folders();
    }
    if (!send_all(fd, &rc, sizeof rc) || rc > 128) ::_exit(rc > 128 ? rc : 0);
  }
  ::_exit(0);  // the parent's end closed: no more jobs (the parent's exit handlers are not this process's)
}

}  // namespace

RunWorker::RunWorker(std::function<std::string(std::size_t)> log, std::function<int(std::size_t)> job)
    : log_(std::move(log)), job_(std::move(job)) {}

RunWorker::~RunWorker() {
  if (pid_ >= 0) reap();
}

void RunWorker::start() {
  std::lock_guard<std::mutex> lock(g_sockets_mutex);
  int sv[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return;
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(sv[0]), ::close(sv[1]);
    return;
  }
  if (pid == 0) {
    // The worker. Output another thread of the parent had buffered is the
    // parent's to print; the parent's output folders and other workers'
    // sockets stay the parent's.
    __fpurge(stdout);
    __fpurge(stderr);
    forget_inherited_output_folders();
    for (int s : g_sockets) ::close(s);
    ::close(sv[0]);
    serve(sv[1], log_, job_);
  }
  ::close(sv[1]);
  pid_ = pid, fd_ = sv[0];
  g_sockets.push_back(fd_);
}

int RunWorker::reap() {
  {
    std::lock_guard<std::mutex> lock(g_sockets_mutex);
    g_sockets.erase(std::remove(g_sockets.begin(), g_sockets.end(), fd_), g_sockets.end());
    ::close(fd_);
  }
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1, fd_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

int RunWorker::run(std::size_t i) {
  const std::uint64_t index = i;
  // A worker that ended between jobs (it should not) is replaced once.
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (pid_ < 0) start();
    if (pid_ < 0) {
      std::fprintf(stderr, "rpfem: error: cannot start a worker process: %s\n", std::strerror(errno));
      return 2;
    }
    if (!send_all(fd_, &index, sizeof index)) {
      reap();
      continue;
    }
    std::int32_t rc;
    if (!recv_all(fd_, &rc, sizeof rc)) return reap();  // ended during the job: its signal or exit code
    if (rc > 128) reap();
    return rc;
  }
  return 2;
}

}  // namespace rpfem
