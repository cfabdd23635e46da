// A worker process for the local pool's runs: a fork(2) of this process,
// without exec, that runs the jobs it is sent one after another, each with
// its standard output and error in a log file of its own, and answers
// each job's exit code.
//
// Why a process, and why one for many runs (docs/decisions.md, "The
// local pool's runs in forked worker processes"): a run stays out of the
// pool's process, so a run that crashes ends its worker, not the study,
// and is reported with its signal; but a new `rpfem run` process cost
// about 87 ms of CPU for a one-step run (57 ms of it the program's start,
// mostly the dynamic loader), a fork per run 57 ms (copy-on-write faults,
// lazy symbol binding, the HDF5 library's start in each child), and a run
// after another in one process 17 ms. A worker runs its runs one after
// another, as `rpfem run --variant all` does.
#pragma once
#include <sys/types.h>

#include <cstddef>
#include <functional>
#include <string>

namespace rpfem {

class RunWorker {
 public:
  // log(i): the file job i writes its output to (created or emptied);
  // job(i): the job, run in the worker process, its return the job's exit
  // code (an exception: report_errors' code and message). Both are called
  // in the worker, on its copy of this process's memory as it was when the
  // worker started.
  RunWorker(std::function<std::string(std::size_t)> log, std::function<int(std::size_t)> job);
  ~RunWorker();  // the worker told to end (its socket closed) and waited for
  RunWorker(const RunWorker&) = delete;
  RunWorker& operator=(const RunWorker&) = delete;

  // Runs job i in the worker process (started if there is none): its exit
  // code; 128 + N if the worker ended by signal N during the job (the next
  // job starts a new worker); 2 if its log cannot be written. A job that
  // ends above 128 (interrupted: the signal stays recorded in the process)
  // ends its worker too.
  int run(std::size_t i);

 private:
  void start();
  int reap();  // the worker's end: its socket closed, its exit status as run() reports it

  std::function<std::string(std::size_t)> log_;
  std::function<int(std::size_t)> job_;
  pid_t pid_ = -1;
  int fd_ = -1;  // this end of the socket to the worker
};

}  // namespace rpfem
