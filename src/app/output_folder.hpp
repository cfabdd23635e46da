// The output folder a command writes into (--out): created if missing and
// owned by this process until it exits. A name that cannot be one (empty,
// under a file, a file itself, too long, on a read-only or missing file
// system) is bad input, said so with the option and the system's reason,
// not an internal error; so is a folder another rpfem process owns.
//
// Ownership is DIR/.rpfem.lock, locked with flock(2) and holding the
// owner's pid: the kernel drops the lock when the process ends however it
// ends (a file left by a killed process is not held, and the next run
// takes it over), and the file is removed at a normal exit.
#pragma once
#include <string>
#include <vector>

namespace rpfem {

// Creates and locks `dir` (again in the same process: nothing). Throws
// InputError naming `option` (e.g. "--out") and `dir`, and for a folder
// in use the pid of the process that holds it.
void make_output_folder(const std::string& dir, const std::string& option = "--out");

// In a child forked from this process (app/subprocess.hpp, run_forked):
// the parent's folders are no longer held here (their descriptors closed,
// their lock files left to the parent, which still holds them).
void forget_inherited_output_folders();
// Releases every folder this process holds (lock files removed), as its
// normal exit does: a forked child's end, which skips the exit handlers.
void release_output_folders();

// What a command does with a folder that already holds something.
enum class ExistingOutput {
  Refuse,   // bad input: a new or empty folder is expected (the default)
  Replace,  // suite, sweep, calibrate --force: what rpfem wrote there before, in every subfolder, is removed first
  Keep,     // run --force (the run replaces its own files as it starts: remove_run_results, and a pool's
            // run.log is the one being written), pools' --resume (finished runs are not run again)
};

// The top-level --out of a command: make_output_folder, then a folder
// that holds anything (a stale lock file aside) is refused, cleared of
// earlier outputs or kept, as `existing` says. `resume_hint`: the command
// has --resume (named in the refusal).
// --force and --resume as one choice (both: --resume; CLI11 excludes it).
inline ExistingOutput existing_output(bool force, bool resume) {
  return resume ? ExistingOutput::Keep : force ? ExistingOutput::Replace : ExistingOutput::Refuse;
}
void claim_output_folder(const std::string& dir, ExistingOutput existing, bool resume_hint = false,
                         const std::string& option = "--out");

// Removes, in `dir` and every folder below it, what rpfem commands write:
// the runs' files (as remove_run_results, and a pool's run.log and
// exit_code), the suite's, sweeps' and calibrations' tables and JSON, the
// report (report.html, report.md, report_files/) and the Slurm engine's
// folder (slurm/); then the subfolders left empty. Anything else is kept.
// A run folder below that another rpfem process owns is bad input.
void remove_previous_outputs(const std::string& dir);

// What a run leaves in its folder (result.h5, result.xdmf, history.csv,
// summary.json, events.csv, and the temporaries they are written under):
// removed before a run writes, so nothing of a previous run is left to be
// mixed with the new one's (a run that stops at step 0 writes no
// result.xdmf). Nothing else in the folder is touched.
void remove_run_results(const std::string& dir);

// The subfolders of `parent` that hold a variant run (its summary.json
// names the subfolder as its variant) whose name is not in `keep`: their
// run files (as above, and the pool's run.log) are removed, then the
// subfolder if it is left empty. A subfolder another process writes into
// is bad input (InputError naming it and the pid).
void remove_stale_variant_runs(const std::string& parent, const std::vector<std::string>& keep);

}  // namespace rpfem
