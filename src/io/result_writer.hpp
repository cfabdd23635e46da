// Writes a run's results as it goes: DIR/result.h5 (HDF5), DIR/result.xdmf
// (so ParaView opens the time series: a block per body and per die),
// DIR/result_meshio*.xdmf (for meshio) and DIR/history.csv. Every finished
// step is flushed to disk before write_step returns, and result.h5 is
// always a file whose last flush finished (each change goes to a spare
// copy first, and the names are exchanged), so a killed run keeps every
// finished step. The XDMF files, rewritten whole, follow at most a second
// behind, and are whole at a run's end. Layout: docs/results-format.md.
#pragma once
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "mesh/mesh.hpp"

namespace rpfem {

// One recorded step's fields. Node fields have one row per node, element
// fields one value per element. Extra fields (contact pressure, ...) are
// written under their map key. Values must be finite: a non-finite value is
// a programming error and write_step throws std::logic_error before writing.
struct StepFields {
  int step = 0;
  double time = 0.0;    // s
  double stroke = 0.0;  // mm
  const std::vector<Vec2>* x = nullptr;      // node coordinates, mm
  const std::vector<Vec2>* v = nullptr;      // node velocities, mm/s
  const std::vector<double>* strain_rate = nullptr;  // element effective strain rate, 1/s
  const std::vector<double>* strain = nullptr;       // element effective strain
  const std::vector<double>* mean_stress = nullptr;  // element mean stress, MPa
  std::map<std::string, std::vector<double>> node_scalars;     // extra, per node
  std::map<std::string, std::vector<double>> element_scalars;  // extra, per element
  // Values of the whole step (XDMF grid attributes, for plots over time):
  // each load component as history.csv names it ("<group>.Fy", N, N/mm in
  // plane strain), each monitor as its column.
  std::vector<std::pair<std::string, double>> globals;
  // Each rigid die's profile at the step's time, a polyline in walking
  // order (mm); a die has the same number of points at every step.
  std::vector<std::pair<std::string, std::vector<Vec2>>> dies;
};

class ResultWriter {
 public:
  // Creates DIR (and parents) if needed, writes the mesh topology and the
  // run metadata (a JSON text stored as the attribute /metadata/json)
  // into DIR/result.h5.partial, flushes it and renames it DIR/result.h5.
  // Each body's nodes and elements must be contiguous (Mesh::append keeps
  // them so).
  ResultWriter(const std::string& dir, const Mesh& mesh, const std::string& metadata_json);
  ~ResultWriter();
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  // A remesh: the steps from first_step on are on `mesh` (its coordinates
  // the remesh's configuration), stored as /meshes/NNNNNN (first_step);
  // each step group names its mesh (attribute "mesh").
  void set_mesh(const Mesh& mesh, int first_step);
  void write_step(const StepFields& f);          // result.h5 + the XDMF files
  void update_metadata(const std::string& json);  // rewrite /metadata/json
  int steps_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// history.csv: one row per step, columns fixed at construction (the header
// written atomically); each row is flushed as it is written.
class HistoryWriter {
 public:
  HistoryWriter(const std::string& path, std::vector<std::string> columns);
  void write_row(const std::vector<double>& values);  // same length as columns
 private:
  std::string path_;
  std::size_t ncols_;
};

// Writes text to path atomically (temporary file + rename), so a reader never
// sees a half-written summary.json; the second form writes its pieces one
// after the other (no copy of them joined).
void write_text_atomically(const std::string& path, const std::string& text);
void write_text_atomically(const std::string& path, std::initializer_list<std::string_view> pieces);

}  // namespace rpfem
