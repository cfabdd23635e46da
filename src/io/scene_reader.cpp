#include "io/scene_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <thread>

#include "mesh/generate.hpp"
#include "mesh/quality.hpp"

namespace rpfem {

namespace {

FlowStressLaw read_material(CaseSection m, std::string& name) {
  FlowStressLaw law;
  const auto lib_names = library_material_names();
  if (m.has("library")) {
    name = m.text("library", std::nullopt);
    const LibraryMaterial* lib = find_library_material(name);
    if (!lib) m.fail("library", "expected one of " + lib_names + ", got \"" + name + "\"");
    law.K = lib->K_kgf_mm2 * kKgfPerMm2ToMPa;
    law.n = lib->n;
  } else {
    name = "custom";
    const bool in_kgf = m.has("K_kgf_mm2");
    if (in_kgf && m.has("K")) m.fail("K", "give K (MPa) or K_kgf_mm2, not both");
    law.K = in_kgf ? m.real("K_kgf_mm2", std::nullopt, Range::positive(), "kgf/mm^2") * kKgfPerMm2ToMPa
                   : m.real("K", std::nullopt, Range::positive(), "MPa");
    law.n = m.real("n", std::nullopt, {0, 1}, "");
  }
  law.eps0 = m.real("eps0", 0.01, {0, 1, true, false}, "");
  law.m = m.real("m", 0.0, {0, 1}, "");
  law.rate_ref = m.real("rate_ref", 1.0, Range::positive(), "1/s");
  return law;
}

// [run]'s mesh factor (it scales every body's division counts: the
// suite's --quick, 0.5) and the limits on the whole mesh and the steps,
// checked before anything that size is built.
struct RunLimits {
  double mesh_factor = 1;
  Index max_elements = 0, max_nodes = 0;
  int max_steps = 0;
  Index elements = 0, nodes = 0;  // over the bodies read so far
};

// The elements a body's mesh will have (`divisions`: how, for the message)
// against what run.max_elements leaves: the mesh is not generated past it.
void check_elements(CaseSection& s, double count, const std::string& divisions, const RunLimits& lim) {
  const double total = count + static_cast<double>(lim.elements);
  if (total <= static_cast<double>(lim.max_elements)) return;
  char text[320];
  std::snprintf(text, sizeof text,
                "%.6g elements (%s at run.mesh_factor %g), %.6g over all bodies; expected at most run.max_elements "
                "= %lld (about 4 kB of memory each; raise it in [run] if the machine has it)",
                count, divisions.c_str(), lim.mesh_factor, total, static_cast<long long>(lim.max_elements));
  s.fail("", text);
}

// A division count times the run's mesh factor, rounded, at least `lo`.
int divisions(CaseSection& s, const std::string& key, std::optional<int> def, int lo, double factor) {
  const int n = s.integer(key, def, lo, 100000);
  return std::max(lo, static_cast<int>(std::lround(n * factor)));
}

// The mesh generator's own checks (convex corners, grid points that
// coincide) name the body only: here they name the file and the key.
template <class Make>
Mesh generated(CaseSection& s, const std::string& key, const std::string& body, Make make) {
  try {
    return make();
  } catch (const InputError& e) {
    std::string what = e.what();
    const std::string prefix = "mesh of '" + body + "': ";
    if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
    s.fail(key, what);
  }
}

Mesh read_mesh(CaseSection s, const std::string& body, const RunLimits& lim) {
  const double factor = lim.mesh_factor;
  auto grid = [](int a, int b, const char* na, const char* nb) {
    return std::string(na) + " " + std::to_string(a) + " x " + nb + " " + std::to_string(b);
  };
  const std::string shape = s.text("shape", std::nullopt, {"rectangle", "quadrilateral", "ring", "disk"});
  Mesh mesh;
  if (shape == "rectangle") {
    RectangleSpec r;
    r.x0 = s.real("x0", 0.0, Range::any(), "mm");
    r.y0 = s.real("y0", 0.0, Range::any(), "mm");
    r.width = s.real("width", std::nullopt, Range::positive(), "mm");
    r.height = s.real("height", std::nullopt, Range::positive(), "mm");
    r.nx = divisions(s, "nx", std::nullopt, 1, factor);
    r.ny = divisions(s, "ny", std::nullopt, 1, factor);
    check_elements(s, double(r.nx) * r.ny, grid(r.nx, r.ny, "nx", "ny"), lim);
    mesh = generated(s, "", body, [&] { return make_rectangle(body, r); });
  } else if (shape == "quadrilateral") {
    QuadrilateralSpec q;
    const std::vector<double> c = s.real_array("corners", 8, "x, y of the 4 corners (mm), counter-clockwise");
    for (int i = 0; i < 4; ++i) q.corners[i] = Vec2(c[2 * i], c[2 * i + 1]);
    q.nx = divisions(s, "nx", std::nullopt, 1, factor);
    q.ny = divisions(s, "ny", std::nullopt, 1, factor);
    check_elements(s, double(q.nx) * q.ny, grid(q.nx, q.ny, "nx", "ny"), lim);
    mesh = generated(s, "corners", body, [&] { return make_quadrilateral(body, q); });
  } else if (shape == "ring") {
    RingSpec r;
    r.inner_radius = s.real("inner_radius", std::nullopt, Range::positive(), "mm");
    r.outer_radius = s.real("outer_radius", std::nullopt, {r.inner_radius, INFINITY, true, false}, "mm");
    r.y0 = s.real("y0", 0.0, Range::any(), "mm");
    r.height = s.real("height", std::nullopt, Range::positive(), "mm");
    r.nr = divisions(s, "nr", std::nullopt, 1, factor);
    r.ny = divisions(s, "ny", std::nullopt, 1, factor);
    check_elements(s, double(r.nr) * r.ny, grid(r.nr, r.ny, "nr", "ny"), lim);
    mesh = generated(s, "", body, [&] { return make_ring(body, r); });
  } else {
    DiskSpec d;
    d.radius = s.real("radius", std::nullopt, Range::positive(), "mm");
    d.center_y = s.real("center_y", 0.0, Range::any(), "mm");
    const std::string part = s.text("part", "half", {"half", "upper_quarter", "lower_quarter"});
    d.part = part == "half" ? DiskPart::Half : part == "upper_quarter" ? DiskPart::UpperQuarter : DiskPart::LowerQuarter;
    d.n = divisions(s, "n", 8, 1, factor);
    d.layers = divisions(s, "layers", 8, 1, factor);
    // Per quarter an n x n block and two layers x n blocks.
    const double quarter = double(d.n) * d.n + 2.0 * d.layers * d.n;
    check_elements(s, (d.part == DiskPart::Half ? 2 : 1) * quarter, grid(d.n, d.layers, "n", "layers"), lim);
    mesh = generated(s, "", body, [&] { return make_disk(body, d); });
  }
  return mesh;
}

// A friction law's table ([dies.NAME.friction], [contact_pairs.friction]).
FrictionLaw read_friction(CaseSection f) {
  FrictionLaw out;
  const std::string law = f.text("law", "none", {"none", "factor", "coulomb"});
  // The other laws' coefficients may stay in the file (so a variant can
  // switch the law by one key); they are not used.
  for (const char* k : {"m", "mu", "a", "regularization"})
    if (!(law == "factor" && std::string(k) != "mu") && !(law == "coulomb" && std::string(k) != "m")) f.ignore(k);
  if (law == "factor") {
    out.kind = FrictionLaw::Kind::Factor;
    out.m = f.real("m", std::nullopt, {0, 1}, "friction factor");
  } else if (law == "coulomb") {
    out.kind = FrictionLaw::Kind::Coulomb;
    out.mu = f.real("mu", std::nullopt, Range::nonnegative(), "Coulomb coefficient");
  }
  if (law == "none") return out;
  // Unset: the enforcement's default (exact under ssn, arctan elsewhere);
  // an enforcement that cannot treat the law as asked refuses the run.
  if (f.has("regularization")) {
    const std::string r = f.text("regularization", "arctan", {"arctan", "exact"});
    out.treatment = r == "exact" ? FrictionLaw::Treatment::Exact : FrictionLaw::Treatment::Arctan;
  }
  if (out.treatment == FrictionLaw::Treatment::Exact) f.ignore("a");
  else out.a_relative = f.real("a", 1e-3, Range::positive(), "arctan smoothing speed, relative to the largest prescribed speed");
  return out;
}

// "a, b" -> {"a", "b"}, each trimmed of spaces ("" -> {""}).
std::vector<std::string> comma_list(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t a = 0, b; a <= text.size(); a = b + 1) {
    b = text.find(',', a);
    if (b == std::string::npos) b = text.size();
    std::string item = text.substr(a, b - a);
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    out.push_back(item);
  }
  return out;
}

// "a, b" -> {"body.a", "body.b"}, each a side of the body's mesh.
std::vector<std::string> side_list(CaseSection& c, const std::string& key, const std::string& body, const Mesh& mesh) {
  std::vector<std::string> out;
  for (const std::string& side : comma_list(c.text(key, "boundary"))) {
    const std::string full = body + "." + side;
    if (!mesh.sides.count(full)) c.fail(key, "no side '" + full + "' on the mesh");
    out.push_back(full);
  }
  return out;
}

// [run]: name, description, geometry, formulation, tolerances, the mesh
// factor and the limits.
RunLimits read_run(CaseSection run, const std::string& file, Scene& sc) {
  sc.name = run.name("name", std::filesystem::path(file).stem().string());
  sc.description = run.text("description", "");
  const std::string geom = run.text("geometry", std::nullopt, {"axisymmetric", "plane_strain"});
  sc.geometry = geom == "axisymmetric" ? Geometry::Axisymmetric : Geometry::PlaneStrain;
  sc.formulation = run.text("formulation", "none");
  if (run.has("suite_formulations"))
    sc.suite_formulations = run.text_array("suite_formulations", "the formulations `rpfem suite` runs on this scene");
  RunLimits lim;
  lim.mesh_factor = run.real("mesh_factor", 1.0, {0, 16, true, false}, "times each mesh's divisions");
  sc.penetration_tolerance =
      run.real("penetration_tolerance", 1e-3, Range::positive(), "largest penetration / element size accepted");
  sc.min_scaled_jacobian = run.real("min_scaled_jacobian", 0.1, {-1, 1, false, false},
                                    "least scaled Jacobian a run without remeshing accepts without a warning");
  constexpr int kMost = std::numeric_limits<int>::max();
  lim.max_elements = run.integer("max_elements", 2000000, 1, kMost);
  lim.max_nodes = run.integer("max_nodes", 2500000, 1, kMost);
  lim.max_steps = run.integer("max_steps", 10000000, 1, kMost);
  sc.max_elements = lim.max_elements, sc.max_nodes = lim.max_nodes;
  return lim;
}

// A body's generated mesh, rejected if an element is inverted or, in
// axisymmetry, the body reaches r < 0.
Mesh read_checked_mesh(CaseSection& b, const std::string& name, RunLimits& lim, Geometry geometry) {
  Mesh m = read_mesh(b.required_table("mesh"), name, lim);
  lim.elements += m.num_elements(), lim.nodes += m.num_nodes();
  if (lim.nodes > lim.max_nodes)
    b.fail("mesh", std::to_string(m.num_nodes()) + " nodes, " + std::to_string(lim.nodes) +
                       " over all bodies; expected at most run.max_nodes = " + std::to_string(lim.max_nodes) +
                       " (raise it in [run] if the machine has the memory)");
  const MeshQuality q = mesh_quality(m);
  if (!(q.min_scaled_jacobian > 0))
    b.fail("mesh", "the generated mesh has an inverted or degenerate element (min scaled Jacobian " +
                       std::to_string(q.min_scaled_jacobian) + ")");
  if (geometry == Geometry::Axisymmetric)
    for (const auto& p : m.x)
      if (p(0) < -1e-12) b.fail("mesh", "an axisymmetric body must lie at r >= 0");
  return m;
}

// A body's [[bodies.NAME.velocity]] and [[bodies.NAME.traction]] tables,
// each on a side of its mesh (already in sc.mesh).
void read_body_loads(CaseSection& b, const std::string& name, Scene& sc) {
  for (CaseSection v : b.table_array("velocity")) {
    VelocityGroup g;
    g.body = name;
    g.side = name + "." + v.text("side", std::nullopt);
    g.name = v.name("name", g.side);
    if (!sc.mesh.sides.count(g.side)) v.fail("side", "no side '" + g.side + "' on this body's mesh");
    g.vx = v.optional_real("vx", Range::any(), "mm/s");
    g.vy = v.optional_real("vy", Range::any(), "mm/s");
    if (!g.vx && !g.vy) v.fail("vx", "give vx, vy or both (mm/s)");
    sc.velocities.push_back(g);
  }
  for (CaseSection t : b.table_array("traction")) {
    TractionLoad l;
    l.side = name + "." + t.text("side", std::nullopt);
    if (!sc.mesh.sides.count(l.side)) t.fail("side", "no side '" + l.side + "' on this body's mesh");
    l.pressure = t.real("pressure", 0.0, Range::any(), "MPa");
    l.t = Vec2(t.real("tx", 0.0, Range::any(), "MPa"), t.real("ty", 0.0, Range::any(), "MPa"));
    sc.tractions.push_back(l);
  }
}

// [bodies.NAME]: material, mesh (appended to sc.mesh), velocities, tractions.
void read_bodies(CaseSection& root, RunLimits& lim, Scene& sc) {
  CaseSection bodies = root.required_table("bodies");
  if (bodies.keys().empty()) bodies.fail("", "at least one body is required");
  for (const auto& name : bodies.keys()) {
    bodies.check_name(name);
    CaseSection b = bodies.required_table(name);
    BodySpec spec;
    spec.name = name;
    CaseSection mat = b.required_table("material");
    spec.law = read_material(mat, spec.material_name);
    spec.alpha_relative = mat.optional_real("alpha", Range::positive(), "relative, replaces solver.alpha for this body");
    sc.mesh.append(read_checked_mesh(b, name, lim, sc.geometry));
    sc.bodies.push_back(spec);
    read_body_loads(b, name, sc);
  }
}

// [[symmetry]] planes; in axisymmetry only planes normal to y.
void read_symmetry(CaseSection& root, Scene& sc) {
  for (CaseSection s : root.table_array("symmetry")) {
    SymmetryPlane p;
    p.axis = s.text("normal", std::nullopt, {"x", "y"}) == "x" ? 0 : 1;
    p.at = s.real("at", 0.0, Range::any(), "mm");
    if (sc.geometry == Geometry::Axisymmetric && p.axis == 0)
      s.fail("normal", "in axisymmetry the axis r = 0 is built in; only planes normal to 'y' (z) apply");
    // The plane holds the nodes on it (model/boundary.cpp, to the same
    // tolerance): one through no node holds nothing, and the run (its
    // loads and volume doubled) would describe a body that is not there.
    const double tol = 1e-9 * sc.mesh.size();
    double lo = INFINITY, hi = -INFINITY;
    for (const Vec2& x : sc.mesh.x) lo = std::min(lo, x(p.axis)), hi = std::max(hi, x(p.axis));
    if (!std::any_of(sc.mesh.x.begin(), sc.mesh.x.end(), [&](const Vec2& x) { return std::abs(x(p.axis) - p.at) <= tol; })) {
      const std::string c = p.axis == 0 ? "x" : "y";
      s.fail("at", "the plane " + c + " = " + std::to_string(p.at) + " mm holds no node (the bodies span " + c + " = " +
                       std::to_string(lo) + " to " + std::to_string(hi) +
                       " mm); a symmetry plane must hold nodes of a body (a side of its mesh on the plane)");
    }
    sc.symmetry.push_back(p);
  }
}

// A die's outline: its [[dies.NAME.vertex]] points with their fillets.
DieProfile read_die_profile(CaseSection& d, const std::string& name) {
  std::vector<Vec2> vertices;
  std::vector<double> fillets;
  for (CaseSection v : d.table_array("vertex")) {
    vertices.emplace_back(v.real("x", std::nullopt, Range::any(), "mm"), v.real("y", std::nullopt, Range::any(), "mm"));
    fillets.push_back(v.real("fillet", 0.0, Range::nonnegative(), "mm"));
  }
  if (vertices.size() < 2) d.fail("vertex", "a die needs at least two [[dies." + name + ".vertex]] entries");
  // Every segment of positive length: two coincident vertices make a
  // segment with no normal (penalty and ipopt ran on with no contact).
  double extent = 0;
  for (const Vec2& p : vertices) extent = std::max(extent, (p - vertices[0]).norm());
  for (std::size_t k = 1; k < vertices.size(); ++k)
    if ((vertices[k] - vertices[k - 1]).norm() <= 1e-12 * std::max(extent, 1.0))
      d.fail("vertex." + std::to_string(k), "coincides with vertex " + std::to_string(k - 1) +
                                               " (x = " + std::to_string(vertices[k](0)) + ", y = " +
                                               std::to_string(vertices[k](1)) +
                                               " mm): expected segments of positive length");
  // Each fillet rounds the corner between its two segments, its arc
  // within both (and clear of the next fillet's): one that does not fit
  // made a profile that doubles back on itself.
  const std::size_t last = vertices.size() - 1;
  std::vector<double> tangent(vertices.size(), 0.0);
  for (std::size_t k = 0; k <= last; ++k) {
    if (!(fillets[k] > 0)) continue;
    const std::string key = "vertex." + std::to_string(k) + ".fillet";
    if (k == 0 || k == last)
      d.fail(key, "vertex " + std::to_string(k) + " is an end of the profile; a fillet rounds the corner between two segments");
    tangent[k] = fillet_tangent_length(vertices[k - 1], vertices[k], vertices[k + 1], fillets[k]);
    const double before = (vertices[k] - vertices[k - 1]).norm(), after = (vertices[k + 1] - vertices[k]).norm();
    if (!(tangent[k] > 0))
      d.fail(key, "a fillet of " + std::to_string(fillets[k]) + " mm where the profile runs straight on (its segments, " +
                      std::to_string(before) + " and " + std::to_string(after) +
                      " mm long, are collinear): there is no corner to round; expected 0, or a fillet at a vertex "
                      "where the profile turns");
    if (tangent[k] > std::min(before, after) * (1 + 1e-12))
      d.fail(key, "a fillet of " + std::to_string(fillets[k]) + " mm does not fit between its segments (" +
                      std::to_string(before) + " and " + std::to_string(after) + " mm long): its arc takes " +
                      std::to_string(tangent[k]) + " mm of each; expected at most " +
                      std::to_string(fillets[k] * std::min(before, after) / tangent[k]) + " mm");
    if (k > 1 && tangent[k] + tangent[k - 1] > before * (1 + 1e-12))
      d.fail(key, "the fillets at vertices " + std::to_string(k - 1) + " and " + std::to_string(k) +
                      " do not fit on the segment between them (" + std::to_string(before) + " mm long): their arcs take " +
                      std::to_string(tangent[k - 1]) + " and " + std::to_string(tangent[k]) +
                      " mm of it; expected fillets whose arcs fit between their segments");
  }
  try {
    return DieProfile(vertices, fillets);
  } catch (const std::invalid_argument& e) {
    d.fail("vertex", e.what());
  }
}

// A die's motion: a constant vx, vy or a velocity_table of (t, vx, vy) rows.
DieMotion read_die_motion(CaseSection& d) {
  const bool table = d.has("velocity_table");
  if (table && (d.has("vx") || d.has("vy"))) d.fail("velocity_table", "give vx/vy or velocity_table, not both");
  if (!table) return DieMotion(Vec2(d.real("vx", 0.0, Range::any(), "mm/s"), d.real("vy", 0.0, Range::any(), "mm/s")));
  std::vector<std::array<double, 3>> rows;
  for (CaseSection r : d.table_array("velocity_table"))
    rows.push_back({r.real("t", std::nullopt, Range::nonnegative(), "s"), r.real("vx", 0.0, Range::any(), "mm/s"),
                    r.real("vy", 0.0, Range::any(), "mm/s")});
  try {
    return DieMotion(rows);
  } catch (const std::invalid_argument& e) {
    d.fail("velocity_table", e.what());
  }
}

// [dies.NAME]: the rigid dies, each with its profile, motion and friction.
void read_dies(CaseSection& root, Scene& sc) {
  auto dies = root.table("dies");
  if (!dies) return;
  for (const auto& name : dies->keys()) {
    dies->check_name(name);
    CaseSection d = dies->required_table(name);
    Die die;
    die.name = name;
    die.profile = read_die_profile(d, name);
    die.motion = read_die_motion(d);
    die.friction = read_friction(d.section("friction"));
    sc.dies.push_back(die);
  }
}

// One [[contact_pairs]] entry: a body's sides against a rigid die or
// another body's sides.
ContactPair read_contact_pair(CaseSection& c, const Scene& sc) {
  ContactPair p;
  auto body_id = [&](const std::string& name) {
    for (int b = 0; b < static_cast<int>(sc.bodies.size()); ++b)
      if (sc.bodies[b].name == name) return b;
    return -1;
  };
  p.body = c.text("body", std::nullopt);
  p.body_id = body_id(p.body);
  if (p.body_id < 0) c.fail("body", "no body named '" + p.body + "'");
  p.sides = side_list(c, "sides", p.body, sc.mesh);
  if (c.has("die") == c.has("with")) c.fail("die", "give either 'die' (a rigid die) or 'with' (another body)");
  if (c.has("die")) {
    p.die = c.text("die", std::nullopt);
    for (int d = 0; d < static_cast<int>(sc.dies.size()); ++d)
      if (sc.dies[d].name == p.die) p.die_id = d;
    if (p.die_id < 0) c.fail("die", "no die named '" + p.die + "'");
    if (c.has("with_sides")) c.fail("with_sides", "only with 'with' (another body)");
    if (c.has("friction")) c.fail("friction", "friction on a die is set in [dies.NAME.friction]");
  } else {
    p.with_body = c.text("with", std::nullopt);
    p.with_body_id = body_id(p.with_body);
    if (p.with_body_id < 0) c.fail("with", "no body named '" + p.with_body + "'");
    if (p.with_body == p.body) c.fail("with", "a body in contact with itself is not supported");
    p.with_sides = side_list(c, "with_sides", p.with_body, sc.mesh);
    p.friction = read_friction(c.section("friction"));
  }
  return p;
}

// [solver]: the kernel's penalty and limiting strain rate, Newton's
// settings, the linear solver.
SolverSpec read_solver(CaseSection solver) {
  SolverSpec out;
  out.alpha_relative = solver.real("alpha", 1e5, Range::positive(), "");
  out.limit_rate_relative = solver.real("limit_strain_rate", 1e-3, Range::positive(), "");
  out.regularization = solver.real("regularization", 0.0, Range::nonnegative(), "");
  auto& nw = out.newton;
  nw.tol_velocity = solver.real("tol_velocity", nw.tol_velocity, Range::positive(), "");
  nw.tol_force = solver.real("tol_force", nw.tol_force, Range::positive(), "");
  nw.max_iterations = solver.integer("max_iterations", nw.max_iterations, 1, 10000);
  nw.direct_iterations = solver.integer("direct_iterations", nw.direct_iterations, 0, 100);
  nw.max_halvings = solver.integer("line_search_halvings", nw.max_halvings, 0, 60);
  nw.secant_after_cut = solver.flag("secant_after_cut", nw.secant_after_cut);
  // A thread count; 0: the machine's cores.
  const auto threads = [&](const char* key) {
    const int n = solver.integer(key, 1, 0, 256);
    return n > 0 ? n : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  };
  out.threads = threads("threads");
  out.blas_threads = threads("blas_threads");
  // "umfpack": LU always, by UMFPACK (lu = "umfpack" implied).
  const std::string ls = solver.text("linear_solver", "auto", {"auto", "cholmod", "lu", "umfpack"});
  out.linear_solver = ls == "cholmod"                   ? LinearSolverChoice::Cholmod
                      : ls == "lu" || ls == "umfpack" ? LinearSolverChoice::Lu
                                                        : LinearSolverChoice::Auto;
  const std::string lu = solver.text("lu", ls == "umfpack" ? "umfpack" : "auto", {"auto", "klu", "umfpack"});
  if (ls == "umfpack" && lu != "umfpack") solver.fail("lu", "'umfpack' where linear_solver is 'umfpack'");
  out.lu = lu == "umfpack" ? LuMode::Umfpack : lu == "klu" ? LuMode::Klu : LuMode::Auto;
  const std::string ch = solver.text("cholesky", "supernodal", {"supernodal", "simplicial", "auto"});
  out.cholesky = ch == "simplicial" ? CholeskyMode::Simplicial
                 : ch == "auto"     ? CholeskyMode::Auto
                                    : CholeskyMode::Supernodal;
  return out;
}

// [stepping]: stroke, increment, the reference velocity group or die
// (default: the first velocity group, else the first die), cuts, output.
void read_stepping(CaseSection st, int max_steps, Scene& sc) {
  sc.stepping.end_stroke = st.real("end_stroke", std::nullopt, Range::positive(), "mm");
  sc.stepping.stroke_increment = st.real("stroke_increment", std::nullopt, {0, sc.stepping.end_stroke, true, false}, "mm");
  sc.stepping.relative_increment = st.real("relative_increment", 0.0, {0, 1, false, true});
  const double steps = sc.stepping.planned_steps_real();
  if (!(steps <= max_steps)) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "%s %.6g steps; expected at most run.max_steps = %d (a larger increment, or raise "
                  "run.max_steps)",
                  sc.stepping.relative_increment > 0 ? "end_stroke, stroke_increment and relative_increment give"
                                                     : "end_stroke / stroke_increment =",
                  steps, max_steps);
    st.fail("stroke_increment", text);
  }
  const std::string def_ref = !sc.velocities.empty() ? sc.velocities.front().name
                              : !sc.dies.empty()      ? sc.dies.front().name
                                                      : std::string();
  sc.stepping.reference = def_ref.empty() ? st.text("reference", std::nullopt) : st.text("reference", def_ref);
  sc.stepping.max_cuts = st.integer("max_cuts", 6, 0, 30);
  sc.stepping.output_every = st.integer("output_every", 1, 1, 1000000);
  sc.stepping.integration =
      st.text("integration", "euler", {"euler", "midpoint"}) == "midpoint" ? TimeIntegration::Midpoint
                                                                          : TimeIntegration::Euler;
  // Step control (model/step_control.hpp): its keys are read, and so
  // recorded, only with a tolerance.
  if (const auto tol = st.optional_real("tolerance", {0, 1, true, true})) {
    SteppingSpec& s = sc.stepping;
    s.tolerance = *tol;
    if (s.relative_increment > 0)
      st.fail("relative_increment",
              "expected no relative_increment where stepping.tolerance is set (the tolerance chooses the "
              "increments)");
    s.min_increment = st.real("min_increment", std::min(1e-5 * s.end_stroke, s.stroke_increment),
                              {0, s.stroke_increment, true, false}, "mm, at most stroke_increment");
    s.max_increment =
        st.real("max_increment", std::max(s.stroke_increment, 0.1 * s.end_stroke),
                {s.stroke_increment, s.end_stroke, false, false}, "mm, from stroke_increment to end_stroke");
    if (!(s.end_stroke / s.min_increment <= max_steps))
      st.fail("min_increment",
              "at least end_stroke / run.max_steps = " + std::to_string(s.end_stroke / max_steps) + " mm");
  } else {
    for (const char* k : {"min_increment", "max_increment"})
      if (st.has(k))
        st.fail("tolerance", std::string("expected a tolerance where stepping.") + k +
                                 " is given (the increments' bounds of the step control)");
  }
}

// [remesh]: off unless enabled; its triggers and target element size.
void read_remesh(CaseSection r, Scene& sc) {
  RemeshSpec& m = sc.remesh;
  m.enabled = r.flag("enabled", false);
  m.min_scaled_jacobian = r.real("min_scaled_jacobian", 0.3, {0, 1, true, false},
                                 "remesh after a step whose least scaled Jacobian is below this");
  m.reject_below = r.real("reject_below", std::min(0.2, m.min_scaled_jacobian), {0, m.min_scaled_jacobian, false, false},
                          "reject a step whose least scaled Jacobian falls below this and remesh the last "
                          "configuration (at most remesh.min_scaled_jacobian)");
  m.stroke_interval = r.real("stroke_interval", 0.0, Range::nonnegative(), "mm of stroke between remeshes (0: never)");
  m.die_interference = r.real("die_interference", 1.0 / 3, Range::nonnegative(),
                              "share of the target element size at a die's corner that the corner may reach into the body (0: never)");
  m.element_size = r.real("element_size", 0.0, Range::nonnegative(), "mm (0: each body's mean initial edge length)");
  m.max_remeshes = r.integer("max_remeshes", 100, 1, 100000);
  m.die_corner_size = r.real("die_corner_size", 0.25, {0.05, 1, false, false},
                             "share of element_size at a die's corner near the body (1: uniform)");
  m.initial_mesh = r.flag("initial_mesh", false);
  m.target_error = r.real("target_error", 0.0, {0, 1, false, true},
                          "target relative strain-rate error of the remeshed bodies (0: off)");
  if (m.target_error > 0) {
    m.min_size = r.real("min_size", 0.2, {0.01, 1, false, false}, "share of element_size, from 0.01 to 1");
    m.max_size = r.real("max_size", 2.0, {m.min_size, 100, false, false},
                        "share of element_size, from remesh.min_size to 100");
  } else {
    for (const char* k : {"min_size", "max_size"})
      if (r.has(k))
        r.fail(k, std::string("expected a remesh.target_error above 0 where remesh.") + k +
                      " is given (the bounds of the size from the error)");
  }
  m.volume_tolerance = r.real("volume_tolerance", 1e-8, {0, 1e-3, false, false},
                              "share of a body's volume its outline's simplification may change per remesh");
  // Which bodies: the names listed, else every body but a virtual rigid one
  // (it hardly deforms, and its outline is a tool's).
  const std::string names = r.text("bodies", "");
  for (const std::string& name : names.empty() ? std::vector<std::string>{} : comma_list(names)) {
    const auto& all = sc.mesh.body_names;
    const auto it = std::find(all.begin(), all.end(), name);
    if (it == all.end()) r.fail("bodies", "a comma-separated list of body names; no body '" + name + "'");
    m.bodies.push_back(static_cast<int>(it - all.begin()));
  }
  if (names.empty())
    for (std::size_t b = 0; b < sc.bodies.size(); ++b)
      if (sc.bodies[b].material_name != "VIRTUAL_RIGID") m.bodies.push_back(static_cast<int>(b));
  std::vector<double> total(sc.mesh.num_bodies(), 0.0);
  std::vector<int> count(sc.mesh.num_bodies(), 0);
  for (Index e = 0; e < sc.mesh.num_elements(); ++e)
    for (int i = 0; i < 4; ++i) {
      total[sc.mesh.element_body[e]] += (sc.mesh.x[sc.mesh.quads[e][(i + 1) % 4]] - sc.mesh.x[sc.mesh.quads[e][i]]).norm();
      ++count[sc.mesh.element_body[e]];
    }
  for (std::size_t b = 0; b < total.size(); ++b)
    m.size.push_back(m.element_size > 0 ? m.element_size : total[b] / std::max(1, count[b]));
}

}  // namespace

Scene read_scene(CaseFile& file) {
  Scene sc;
  sc.file = file.path();
  CaseSection root = file.root();
  RunLimits lim = read_run(root.required_table("run"), file.path(), sc);
  read_bodies(root, lim, sc);
  read_symmetry(root, sc);
  read_dies(root, sc);
  for (CaseSection c : root.table_array("contact_pairs")) sc.contact_pairs.push_back(read_contact_pair(c, sc));
  sc.solver = read_solver(root.section("solver"));
  read_stepping(root.required_table("stepping"), lim.max_steps, sc);
  read_remesh(root.section("remesh"), sc);
  return sc;
}

}  // namespace rpfem
