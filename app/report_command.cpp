// SPDX-License-Identifier: MIT
// `fesph report RUN_DIR...`: report.md comparing runs with each other, with the experiment and
// with published simulations (the scene's [reference]): residual velocity after each plate
// (Table 1 of Hu et al. 2015), velocity histories overlaid, wall times, plate images and holes.
// Everything it shows is read from the run folders; missing images are drawn first.
#include "app/commands.hpp"
#include "app/folder_lock.hpp"

#include "core/common/error.hpp"
#include "core/common/toml_check.hpp"
#include "core/scene/scene.hpp"
#include "render/velocity_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>

namespace fesph {

namespace fs = std::filesystem;

namespace {

using CsvRow = std::map<std::string, std::string>;

// A CSV file with a header line; no quoting (fesph writes none). Missing file: no rows.
std::vector<CsvRow> readCsv(const fs::path& path) {
  std::vector<CsvRow> rows;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return rows;
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');) header.push_back(h);
  while (std::getline(in, line)) {
    CsvRow row;
    std::stringstream ls(line);
    std::string cell;
    for (std::size_t k = 0; k < header.size() && std::getline(ls, cell, ','); ++k)
      row[header[k]] = cell;
    rows.push_back(std::move(row));
  }
  return rows;
}

// A field of the CSV files the report writes, as RFC 4180 has it: quoted, its quotes doubled,
// where it holds a comma, a quote or a line break. Run labels hold commas ("FE-SPH 0.4
// (quick, main)"), and a spreadsheet split them into two columns.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

/// One projectile's rows of residual_velocities.csv: after each plate, NaN where not measured.
struct ProjectileCrossings {
  std::string name;                      ///< empty in a table older than its projectile column
  std::vector<double> residual;          ///< the intact piece's speed, m/s
  std::vector<double> piece_fraction;    ///< its share of the initial mass
  std::vector<double> through_velocity;  ///< all projectile material through the plate, m/s
  std::vector<double> through_fraction;  ///< its share of the initial mass
};

struct ReportRun {
  fs::path dir;
  std::string kind;             ///< e.g. "FE-SPH 0.4"
  std::string label;            ///< e.g. "FE-SPH 0.4 (quick, main)": kind, resolution, folder
  Scene scene;                  ///< the scene as run
  toml::table summary;          ///< summary.toml (empty when the run wrote none)
  /// Each projectile's crossings in the order of the scene's bodies; the first is the one
  /// compared with the experiment.
  std::vector<ProjectileCrossings> projectiles;
  const ProjectileCrossings& compared() const {
    static const ProjectileCrossings none;
    return projectiles.empty() ? none : projectiles.front();
  }
};

/// The run's label with `shown` for its folder (its name, or more of its path).
std::string runLabel(const ReportRun& r, const fs::path& shown) {
  return r.kind + " (" + r.scene.resolution + ", " + shown.string() + ")";
}

double summaryNumber(const ReportRun& r, const char* key) {
  const toml::node* n = r.summary.get(key);
  return n && n->is_number() ? tomlcheck::numberValue(*n) : std::nan("");
}

std::string summaryString(const ReportRun& r, const char* key, const std::string& fallback) {
  const auto v = r.summary[key].value<std::string>();
  return v ? *v : fallback;
}

// "runs/x/" and "runs/x" are the same folder.
fs::path folder(const std::string& dir) {
  fs::path p = fs::absolute(dir).lexically_normal();
  return p.filename().empty() ? p.parent_path() : p;
}

ReportRun readRun(const fs::path& dir) {
  ReportRun r;
  r.dir = dir;
  const fs::path scene = dir / "scene.toml";
  if (!fs::exists(scene) || !fs::exists(dir / "elements.pvd"))
    throw InputError(dir.string(), 0, 0, "not a run folder (it needs scene.toml and elements.pvd)");
  r.scene = loadScene(scene.string());
  if (fs::exists(dir / "summary.toml")) r.summary = tomlcheck::parseFile((dir / "summary.toml").string());
  const ConversionControls& c = r.scene.controls.conversion;
  char label[160];
  if (c.mode == ConversionMode::Sph)
    std::snprintf(label, sizeof label, "FE-SPH %.2g", c.plastic_strain);
  else if (c.mode == ConversionMode::Erosion)
    std::snprintf(label, sizeof label, "erosion %.2g", c.plastic_strain);
  else
    std::snprintf(label, sizeof label, "FE");
  r.kind = label;
  r.label = runLabel(r, dir.filename());
  for (const CsvRow& row : readCsv(dir / "residual_velocities.csv")) {
    auto number = [&](const char* key) {  // NaN: not measured (or a column older runs lack)
      const auto it = row.find(key);
      return it != row.end() && !it->second.empty() ? std::stod(it->second) : std::nan("");
    };
    const auto named = row.find("projectile");
    const std::string name = named != row.end() ? named->second : std::string();
    // a projectile's rows come in a block
    if (r.projectiles.empty() || r.projectiles.back().name != name)
      r.projectiles.push_back({name, {}, {}, {}, {}});
    ProjectileCrossings& p = r.projectiles.back();
    p.residual.push_back(number("residual_velocity_m_s"));
    p.piece_fraction.push_back(number("mass_fraction"));
    p.through_velocity.push_back(number("through_velocity_m_s"));
    p.through_fraction.push_back(number("through_mass_fraction"));
  }
  return r;
}

std::string percent(double fraction) {
  if (!std::isfinite(fraction)) return "-";
  char s[32];
  std::snprintf(s, sizeof s, "%.1f %%", 100 * fraction);
  return s;
}

std::string velocity(double v) {
  if (!std::isfinite(v)) return "-";
  char s[32];
  std::snprintf(s, sizeof s, "%.1f", v);
  return s;
}

/// A reference's velocity in the report: 0 is a projectile that stopped in the plate.
std::string referenceVelocity(double v) { return v == 0 ? "0 (stopped)" : velocity(v); }

// Error against the experiment, (simulation - experiment) / experiment in %.
std::string error(double sim, double exp) {
  // The test stopped in this plate: a run through it has no error to give, but must say so.
  if (exp == 0) return std::isfinite(sim) && sim > 0 ? "through (stopped in the test)" : "-";
  if (!std::isfinite(sim) || !std::isfinite(exp)) return "-";
  char s[32];
  std::snprintf(s, sizeof s, "%+.1f %%", 100 * (sim - exp) / exp);
  return s;
}

double at(const std::vector<double>& v, std::size_t k) {
  return k < v.size() ? v[k] : std::nan("");
}

/// Whether run `r` is of the experiment `ref` (the first run's scene's [reference]): a run is
/// compared only with the experiment its own scene names. A run of another scene (another
/// reference, or none) put beside the first showed errors against an experiment it never had.
bool sameExperiment(const ReportRun& r, const ReferenceData& ref) {
  return r.scene.reference.source == ref.source && r.scene.reference.experiment == ref.experiment;
}

/// The experiment's value at plate k for run `r`; NaN (no error shown) for a run of another.
double experimentFor(const ReportRun& r, const ReferenceData& ref, std::size_t k) {
  return sameExperiment(r, ref) ? at(ref.experiment, k) : std::nan("");
}

// Copy a run's images into the report (drawn first when the run has none). Images of another
// field (`fesph render --field`; holes.json names it, none before it did) are left to the run,
// and the report draws its own damage views.
std::vector<std::string> plateImages(const ReportRun& r, const fs::path& out, int index) {
  fs::path images = r.dir / "images";
  const fs::path dest = out / ("run" + std::to_string(index));
  if (!fs::exists(images / "holes.csv")) {
    renderRun(r.dir.string(), -1.0, "damage", 1200, 900, images.string());
  } else {
    std::ifstream json(images / "holes.json");
    const std::string text((std::istreambuf_iterator<char>(json)),
                           std::istreambuf_iterator<char>());
    if (text.find("\"field\": ") != std::string::npos &&
        text.find("\"field\": \"damage\"") == std::string::npos) {
      renderRun(r.dir.string(), -1.0, "damage", 1200, 900, dest.string());
      images = dest;
    }
  }
  fs::create_directories(dest);
  std::vector<std::string> copied;
  for (const auto& entry : fs::directory_iterator(images)) {
    const fs::path p = entry.path();
    if (p.extension() != ".png" && p.extension() != ".csv" && p.extension() != ".json") continue;
    if (images != dest)
      fs::copy_file(p, dest / p.filename(), fs::copy_options::overwrite_existing);
    if (p.extension() == ".png") copied.push_back((dest.filename() / p.filename()).string());
  }
  std::sort(copied.begin(), copied.end());
  return copied;
}

// Three significant figures, and every figure of a whole number past them (1980, not 1.98e+03).
std::string threeFigures(double v) {
  char text[32];
  std::snprintf(text, sizeof text, std::abs(v) >= 1000 ? "%.0f" : "%.3g", v);
  return text;
}

// The clumps of free particles that would strike a plate, most kinetic energy first
// (debris.csv, written with the images; core/analysis/debris.hpp).
void debrisRows(const std::vector<CsvRow>& clumps, std::ostringstream& md) {
  if (clumps.empty()) return;
  constexpr std::size_t kShown = 10;
  std::vector<const CsvRow*> striking;
  for (const CsvRow& c : clumps)
    if (!c.at("strikes").empty()) striking.push_back(&c);
  // Ranked by kinetic energy, what a fragment's threat to the next plate scales with: a heavy
  // clump that barely drifts matters less than a light one at a few hundred m/s.
  const auto energy = [](const CsvRow& c) {
    const double v = std::stod(c.at("speed_m_s"));
    return 0.5 * std::stod(c.at("full_mass_kg")) * v * v;
  };
  std::stable_sort(striking.begin(), striking.end(), [&](const CsvRow* a, const CsvRow* b) {
    return energy(*a) > energy(*b);
  });
  md << "\nDebris at t = " << clumps.front().at("time_s") << " s: " << clumps.size()
     << (clumps.size() == 1 ? " clump" : " clumps")
     << " of two or more free particles (linked within 1.5 times the sum of their radii), "
     << striking.size() << " of them on a straight course to a plate of another body "
        "(debris.csv)";
  if (striking.empty()) {
    md << ".\n";
    return;
  }
  md << "; the " << std::min(kShown, striking.size()) << " of those with the most kinetic "
     << "energy (mass and energy in the full model: a clump on a half model's plane counts "
        "twice):\n\n"
     << "| from | particles | mass (g) | speed (m/s) | energy (J) | damage | strikes | at (ms) | "
        "where x, y (mm) | normal speed (m/s) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < std::min(kShown, striking.size()); ++k) {
    const CsvRow& c = *striking[k];
    char line[512];
    std::snprintf(line, sizeof line,
                  "| %s | %s | %s | %.0f | %s | %.2f | %s | %.2f | %.0f, %.0f | %.0f |\n",
                  c.at("body").c_str(), c.at("particles").c_str(),
                  threeFigures(1e3 * std::stod(c.at("full_mass_kg"))).c_str(),
                  std::stod(c.at("speed_m_s")), threeFigures(energy(c)).c_str(),
                  std::stod(c.at("damage")), c.at("strikes").c_str(),
                  1e3 * std::stod(c.at("strike_time_s")), 1e3 * std::stod(c.at("strike_x_m")),
                  1e3 * std::stod(c.at("strike_y_m")),
                  std::stod(c.at("strike_normal_speed_m_s")));
    md << line;
  }
}

void debrisSection(const fs::path& csv, std::ostringstream& md) {
  try {
    debrisRows(readCsv(csv), md);
  } catch (const std::exception& e) {  // a column missing (out_of_range) or not a number
    throw RunError(csv.string() + ": not a debris table as fesph writes it (" + e.what() + ")");
  }
}

void writeReport(const std::vector<ReportRun>& runs, const fs::path& out) {
  const Scene& first = runs.front().scene;
  const ReferenceData& ref = first.reference;
  std::size_t plates = ref.experiment.size();
  for (const ReportRun& r : runs)
    for (const ProjectileCrossings& p : r.projectiles) plates = std::max(plates, p.residual.size());

  // Table 1 as CSV and markdown.
  std::ofstream csv(out / "table1.csv");
  csv << "plate,experiment_m_s";
  for (const auto& [label, v] : ref.published) csv << "," << csvField(label + "_m_s");
  for (const ReportRun& r : runs) csv << "," << csvField(r.label + "_m_s");
  csv << "\n";
  std::ostringstream md;
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  md << "# " << first.title << "\n\nReport of " << runs.size() << " run(s), written by fesph "
     << FESPH_VERSION << " on " << date << ".\n\n";
  md << "## Residual velocity after each plate\n\n"
     << "Definition (the one used everywhere in fesph, `core/analysis/plate_crossings.hpp`): the "
        "speed of the projectile's largest intact piece of elements (of a projectile made of "
        "particles, its largest clump of linked particles) at the first instant its leading "
        "node (particle) reaches the plane one clear gap behind the plate's rear face (the "
        "front face of the next plate; a virtual next plate at the same gap after the last one). "
        "Errors are (value - experiment) / experiment; a reference's 0 is a projectile that "
        "stopped in the plate. A - is no value: the run ended (its status and time under Runs) "
        "or its piece stopped before that plane, or there is nothing to compare with.\n\n";
  if (!ref.source.empty()) md << "Reference: " << ref.source << ".\n\n";
  md << "| plate | experiment |";
  for (const auto& [label, v] : ref.published) md << " " << label << " | error |";
  for (const ReportRun& r : runs) md << " " << r.label << " | error |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < ref.published.size() + runs.size(); ++k) md << "---|---|";
  md << "\n";
  for (std::size_t k = 0; k < plates; ++k) {
    const double exp = at(ref.experiment, k);
    md << "| v" << k + 1 << " | " << referenceVelocity(exp) << " |";
    csv << k + 1 << "," << velocity(exp);
    for (const auto& [label, v] : ref.published) {
      md << " " << referenceVelocity(at(v, k)) << " | " << error(at(v, k), exp) << " |";
      csv << "," << velocity(at(v, k));
    }
    for (const ReportRun& r : runs) {
      const std::vector<double>& v = r.compared().residual;
      md << " " << velocity(at(v, k)) << " | " << error(at(v, k), experimentFor(r, ref, k)) << " |";
      csv << "," << velocity(at(v, k));
    }
    md << "\n";
    csv << "\n";
  }
  std::string others;
  for (const ReportRun& r : runs)
    if (!sameExperiment(r, ref))
      others += std::string(others.empty() ? "" : "; ") + r.label + ": \"" + r.scene.title + "\"";
  if (!others.empty())
    md << "\nRuns of another scene than the first (their scene's [reference] differs): " << others
       << ". Their velocities are shown, not compared with this experiment.\n";
  for (const ReportRun& r : runs)
    if (r.projectiles.size() > 1)
      md << "\n" << r.label << " has " << r.projectiles.size() << " projectiles; the table gives "
         << "the scene's first, '" << r.compared().name << "'; the next section gives each one.\n";

  // What of the projectile got through each plate: the intact piece against all its material.
  std::ofstream through_csv(out / "through.csv");
  through_csv << "plate,run,piece_velocity_m_s,piece_mass_fraction,through_velocity_m_s,"
                 "through_mass_fraction,projectile\n";
  md << "\n## What of the projectile got through each plate\n\n"
     << "At the instant v_k is taken: the largest intact piece (its speed is v_k) and all the "
        "projectile's material past the plate's rear face (live elements and the particles born "
        "from its elements, or the particles it is made of), each with its share of the "
        "projectile's initial mass; the second velocity is that material's momentum over its "
        "mass, with its error against the experiment's v_k. Where the projectile breaks up, "
        "its intact rear goes on faster than the material the plate slowed. A run with several "
        "projectiles has a row for each, its name after the run's; only the scene's first is "
        "compared with the experiment.\n\n"
     << "| plate | run | intact piece | its mass | all material through | error | its mass |\n"
        "|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < plates; ++k)
    for (const ReportRun& r : runs)
      for (const ProjectileCrossings& p : r.projectiles) {
        const bool first = &p == &r.projectiles.front();
        const std::string who = r.projectiles.size() > 1 ? r.label + " '" + p.name + "'" : r.label;
        const double v_all = at(p.through_velocity, k);
        md << "| v" << k + 1 << " | " << who << " | " << velocity(at(p.residual, k)) << " | "
           << percent(at(p.piece_fraction, k)) << " | " << velocity(v_all) << " | "
           << error(v_all, first ? experimentFor(r, ref, k) : std::nan("")) << " | "
           << percent(at(p.through_fraction, k)) << " |\n";
        through_csv << k + 1 << "," << csvField(r.label) << "," << velocity(at(p.residual, k))
                    << "," << at(p.piece_fraction, k) << "," << velocity(v_all) << ","
                    << at(p.through_fraction, k) << "," << csvField(p.name) << "\n";
      }

  // Runs: settings, cost, energy budget.
  std::ofstream runs_csv(out / "runs.csv");
  runs_csv << "run,folder,mode,plastic_strain,resolution,elements,particles,steps,time_s,"
              "wall_time_s,threads,energy_balance,status\n";
  // Wall times of runs on different thread counts or machine loads do not compare: the
  // thread count is shown beside them.
  md << "\n## Runs\n\n| run | elements | particles | steps | to t | wall time | threads | "
        "energy balance | status |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const ReportRun& r : runs) {
    const double wall = summaryNumber(r, "wall_time_s");
    const double threads = summaryNumber(r, "threads");
    const std::string status = standingStatus(r.dir.string(), summaryString(r, "status", ""));
    char line[512];
    std::snprintf(line, sizeof line,
                  "| %s | %.0f | %.0f | %.0f | %.4g s | %.*f s | %.0f | %.3g %% | %s |\n",
                  r.label.c_str(), summaryNumber(r, "elements"), summaryNumber(r, "particles"),
                  summaryNumber(r, "steps"), summaryNumber(r, "time"),
                  wall < 100 ? 2 : 0, wall, threads,  // a test run of 0.35 s was "0 s"
                  100 * summaryNumber(r, "energy_balance"),
                  status.empty() ? "no summary.toml" : status.c_str());
    md << line;
    runs_csv << csvField(r.label) << "," << csvField(r.dir.string()) << ","
             << csvField(summaryString(r, "conversion_mode", "")) << ","
             << summaryNumber(r, "plastic_strain") << "," << csvField(r.scene.resolution) << ","
             << summaryNumber(r, "elements") << "," << summaryNumber(r, "particles") << ","
             << summaryNumber(r, "steps") << "," << summaryNumber(r, "time") << "," << wall << ","
             << threads << "," << summaryNumber(r, "energy_balance") << ","
             << csvField(status) << "\n";
  }

  // Half models: no particle may cross a symmetry plane (docs/sph.md, "Symmetry planes"); runs
  // before the mirror images (the ninth session) let them.
  for (const ReportRun& r : runs) {
    const double across = summaryNumber(r, "particles_across_symmetry");
    if (!(across > 0)) continue;
    char line[512];
    std::snprintf(line, sizeof line,
                  "\n**Check failed, %s:** %.0f particle%s (%.4g kg, %.1f %% of the particles' "
                  "mass) %s across the symmetry plane at the end of the run. A half model's "
                  "particles see their mirror images and stay on their side (docs/sph.md, "
                  "\"Symmetry planes\"); a run of a fesph before that, or a defect: its FE-SPH "
                  "results of the half model are not to be trusted.\n",
                  r.label.c_str(), across, across == 1 ? "" : "s",
                  summaryNumber(r, "particle_mass_across_symmetry_kg"),
                  100 * summaryNumber(r, "particle_mass_fraction_across_symmetry"),
                  across == 1 ? "is" : "are");
    md << line;
  }

  // Velocity histories overlaid.
  std::vector<std::pair<std::string, std::string>> curves;
  for (const ReportRun& r : runs) curves.emplace_back(r.label, (r.dir / "history.csv").string());
  ImageOptions o;
  o.width = 1400;
  o.height = 900;
  renderVelocityPlot(curves, "", (out / "velocity.png").string(), o);
  md << "\n## Projectile velocity\n\nMean velocity of the projectile body (elements and the "
        "particles born from it), every run; a run with several projectiles has a curve for "
        "each.\n\n![projectile velocity](velocity.png)\n";

  // Plate images and holes of every run.
  md << "\n## Plates\n\nFront and rear views at each run's last output, coloured by damage; "
        "through-holes are outlined and measured from the geometry (holes.csv).\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    md << "\n### " << runs[i].label << "\n\n";
    bool plates_drawn = false;
    for (const std::string& png : plateImages(runs[i], out, static_cast<int>(i + 1))) {
      md << "![" << fs::path(png).stem().string() << "](" << png << ")\n";
      plates_drawn = plates_drawn || png.find("_front.png") != std::string::npos;
    }
    const fs::path copied = out / ("run" + std::to_string(i + 1));
    const auto holes = readCsv(copied / "holes.csv");
    if (!plates_drawn)
      md << "\nNo plate images: no plate of this run has elements or particles at its last "
            "output.\n";
    else if (holes.empty())
      md << "\nNo through-holes.\n";
    else
      md << "\n| plate | hole | area (mm^2) | equivalent diameter (mm) | centre x, y, z (mm) "
            "|\n|---|---|---|---|---|\n";
    for (const CsvRow& h : holes) {  // the centre tells a fragment's hole from the projectile's
      char line[256];
      std::snprintf(line, sizeof line, "| %s | %s | %.1f | %.2f | %.1f, %.1f, %.1f |\n",
                    h.at("plate").c_str(), h.at("hole").c_str(), 1e6 * std::stod(h.at("area_m2")),
                    1e3 * std::stod(h.at("diameter_m")), 1e3 * std::stod(h.at("centroid_x_m")),
                    1e3 * std::stod(h.at("centroid_y_m")), 1e3 * std::stod(h.at("centroid_z_m")));
      md << line;
    }
    debrisSection(copied / "debris.csv", md);
  }
  std::ofstream(out / "report.md") << md.str();
}

/// Runs whose labels are alike (folders of one name in different places: a/quick, b/quick)
/// are told apart by more of their paths; the same folder twice is bad input.
void distinctLabels(std::vector<ReportRun>& runs) {
  for (std::size_t i = 0; i < runs.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (runs[i].dir == runs[j].dir)
        throw InputError(runs[i].dir.string(), 0, 0, "this run folder is given twice");
  for (int depth = 2; depth < 64; ++depth) {
    bool alike = false;
    for (std::size_t i = 0; i < runs.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (runs[i].label == runs[j].label) {
          alike = true;
          for (ReportRun* r : {&runs[i], &runs[j]}) {
            fs::path shown;  // the folder's last `depth` parts
            fs::path d = r->dir;
            for (int k = 0; k < depth && !d.filename().empty(); ++k, d = d.parent_path())
              shown = shown.empty() ? d.filename() : d.filename() / shown;
            r->label = runLabel(*r, shown);
          }
        }
    if (!alike) return;
  }
}

}  // namespace

int reportCommand(const ReportOptions& opt) {
  std::vector<ReportRun> runs;
  try {
    for (const std::string& dir : opt.run_dirs) runs.push_back(readRun(folder(dir)));
    distinctLabels(runs);
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  for (const ReportRun& r : runs)
    if (!sameExperiment(r, runs.front().scene.reference))
      std::fprintf(stderr,
                   "warning: %s is a run of \"%s\", not of the first run's scene (\"%s\"): its "
                   "velocities are not compared with that scene's experiment\n",
                   r.dir.string().c_str(), r.scene.title.c_str(),
                   runs.front().scene.title.c_str());
  const fs::path out = opt.out.empty() ? runs.front().dir.parent_path() / "report"
                                       : fs::path(opt.out);
  try {
    fs::create_directories(out);
    writeReport(runs, out);
  } catch (const RunError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const fs::filesystem_error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  std::printf("report: %s\n", (out / "report.md").string().c_str());
  return 0;
}

}  // namespace fesph
