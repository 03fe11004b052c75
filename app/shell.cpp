// SPDX-License-Identifier: MIT
// The workbench commands of `fesph shell`. Every command reports its errors and returns; the
// run itself is a RunSession, driven in pieces.
#include "app/shell.hpp"

#include "app/cli_checks.hpp"
#include "app/commands.hpp"
#include "app/folder_lock.hpp"
#include "app/progress.hpp"

#include "core/analysis/fragments.hpp"
#include "core/analysis/plate_crossings.hpp"
#include "core/common/error.hpp"
#include "core/common/number_text.hpp"
#include "core/common/toml_check.hpp"
#include "core/io/checkpoint.hpp"
#include "core/state/model_build.hpp"
#include "render/plate_images.hpp"
#include "render/series_writer.hpp"
#include "render/velocity_plot.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace fesph {

namespace fs = std::filesystem;

namespace {

/// A command used wrongly: the message says how to use it.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A command failed and has printed why.
struct Reported {};

/// Words of a line: split on blanks; # starts a comment. A double quote that opens a word
/// groups blanks into it and is dropped ("my file.toml"); one inside a word is kept, with its
/// closing quote, so that TOML strings stay strings (resolution="quick").
std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::string w;
  bool quoted = false, keep = false, any = false;
  for (char c : line) {
    if (c == '"') {
      if (!quoted) keep = any;
      quoted = !quoted;
      if (keep) w += c;
      any = true;
    } else if (!quoted && c == '#') {
      break;
    } else if (!quoted && std::isspace(static_cast<unsigned char>(c))) {
      if (any) out.push_back(w);
      w.clear();
      any = false;
    } else {
      w += c;
      any = true;
    }
  }
  if (quoted) throw UsageError("unbalanced double quote");
  if (any) out.push_back(w);
  return out;
}

/// A time in s: a number, optionally with a unit s, ms, us or ns ("5e-6", "5us").
double parseTime(const std::string& text) {
  std::size_t used = 0;
  double t = 0;
  try {
    t = std::stod(text, &used);
  } catch (const std::exception&) {
    throw UsageError("'" + text + "' is not a time (e.g. 5e-6 or 5us)");
  }
  const std::string unit = text.substr(used);
  const double scale = unit.empty() || unit == "s" ? 1
                       : unit == "ms"              ? 1e-3
                       : unit == "us"              ? 1e-6
                       : unit == "ns"              ? 1e-9
                                                   : -1;
  if (scale < 0 || !std::isfinite(t) || t < 0)
    throw UsageError("'" + text + "' is not a time (e.g. 5e-6 or 5us)");
  return t * scale;
}

/// A TOML basic string: quoted, with backslashes, quotes and control characters escaped.
std::string tomlString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\t': out += "\\t"; break;
      case '\n': out += "\\n"; break;
      case '\f': out += "\\f"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char code[8];
          std::snprintf(code, sizeof code, "\\u%04x", static_cast<unsigned char>(c));
          out += code;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

/// A TOML value as it would be written in a scene (the library's formatters are off). A float
/// takes the shortest form that reads back as the same double: an exported scene is the scene.
std::string tomlText(const toml::node& node) {
  if (const auto* v = node.as_floating_point()) {
    const std::string s = shortestText(v->get());
    return s.find_first_of(".eEn") == std::string::npos ? s + ".0" : s;
  }
  if (const auto* v = node.as_integer()) return std::to_string(v->get());
  if (const auto* v = node.as_boolean()) return v->get() ? "true" : "false";
  if (const auto* v = node.as_string()) return tomlString(v->get());
  if (const auto* a = node.as_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + tomlText((*a)[i]);
    return s + "]";
  }
  if (const auto* t = node.as_table()) {
    std::string s = "{";
    bool first = true;
    for (const auto& [k, v] : *t) {
      s += (first ? " " : ", ") + std::string(k.str()) + " = " + tomlText(v);
      first = false;
    }
    return s + " }";
  }
  return "(date/time)";
}

/// Scene values as dotted keys and TOML text. A table of an array is named by its `name`
/// when it has one (bodies.plate.shape.thickness), else by its index (boundary.0.type);
/// `by_index`: always by index.
void flatten(const toml::table& t, const std::string& prefix, bool by_index,
             std::vector<std::pair<std::string, std::string>>& out) {
  for (const auto& [k, node] : t) {
    const std::string key = prefix + std::string(k.str());
    if (const toml::table* sub = node.as_table()) {
      flatten(*sub, key + ".", by_index, out);
    } else if (const toml::array* arr = node.as_array(); arr && arr->is_array_of_tables()) {
      for (std::size_t i = 0; i < arr->size(); ++i) {
        const toml::table& e = *(*arr)[i].as_table();
        const std::string name = by_index ? "" : e["name"].value_or(std::string());
        flatten(e, key + "." + (name.empty() ? std::to_string(i) : name) + ".", by_index, out);
      }
    } else {
      out.emplace_back(key, tomlText(node));
    }
  }
}

std::vector<std::pair<std::string, std::string>> sceneValues(const std::string& text,
                                                             bool by_index = false) {
  std::vector<std::pair<std::string, std::string>> out;
  if (text.empty()) return out;
  flatten(tomlcheck::parseText(text, "scene"), "", by_index, out);
  std::sort(out.begin(), out.end());
  return out;
}

/// `value` put at a dotted path of a parsed scene the way loadScene applies --set and
/// resolution presets (which checked it already): through tables (made when missing) and
/// arrays, by index or by the `name` of one of their tables (bodies.plate).
void setPath(toml::table& root, const std::string& dotted, const toml::node& value) {
  std::vector<std::string> parts;
  std::stringstream path(dotted);
  for (std::string p; std::getline(path, p, '.');) parts.push_back(p);
  if (parts.empty()) return;
  toml::node* node = &root;
  for (std::size_t i = 0; i + 1 < parts.size() && node; ++i) {
    const std::string& p = parts[i];
    if (toml::table* t = node->as_table()) {
      node = t->get(p);
      if (!node) node = &t->insert_or_assign(p, toml::table{}).first->second;
    } else if (toml::array* a = node->as_array()) {
      node = nullptr;
      if (!p.empty() && p.find_first_not_of("0123456789") == std::string::npos) {
        node = a->get(std::stoul(p));
      } else {
        for (toml::node& e : *a)
          if (e.is_table() && (*e.as_table())["name"].value_or(std::string()) == p) node = &e;
      }
    } else {
      node = nullptr;
    }
  }
  if (toml::table* t = node ? node->as_table() : nullptr) t->insert_or_assign(parts.back(), value);
}

void applySet(toml::table& root, const std::string& kv) {
  const std::size_t eq = kv.find('=');
  const toml::table value = tomlcheck::parseText("v = " + kv.substr(eq + 1), "--set " + kv);
  setPath(root, kv.substr(0, eq), *value.get("v"));
}

std::string tomlKey(std::string_view k) {
  const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  return bare ? std::string(k) : tomlString(k);
}

/// A scene document as TOML text: values first, then [tables], then [[arrays of tables]].
void writeToml(const toml::table& t, const std::string& header, std::string& out) {
  for (const auto& [k, v] : t) {
    const toml::array* a = v.as_array();
    if (!v.is_table() && !(a && a->is_array_of_tables() && !a->empty()))
      out += tomlKey(k.str()) + " = " + tomlText(v) + "\n";
  }
  for (const auto& [k, v] : t)
    if (const toml::table* sub = v.as_table()) {
      out += "\n[" + header + tomlKey(k.str()) + "]\n";
      writeToml(*sub, header + tomlKey(k.str()) + ".", out);
    }
  for (const auto& [k, v] : t)
    if (const toml::array* a = v.as_array(); a && a->is_array_of_tables() && !a->empty())
      for (const toml::node& e : *a) {
        out += "\n[[" + header + tomlKey(k.str()) + "]]\n";
        writeToml(*e.as_table(), header + tomlKey(k.str()) + ".", out);
      }
}

/// The scene file's text with `overrides` and its resolution preset applied, as loadScene
/// applies them (overrides, the preset, the overrides again so that they win), as TOML.
/// `keep_presets`: keep `resolution` and [resolutions] (shown); without them the text is the
/// same scene on its own (exported).
std::string sceneWithChanges(const std::string& text, const std::string& name,
                             const std::vector<std::string>& overrides, bool keep_presets = true) {
  toml::table root = tomlcheck::parseText(text, name);
  for (const std::string& o : overrides) applySet(root, o);
  const std::string resolution = root["resolution"].value_or(std::string("default"));
  if (const toml::table* preset = root["resolutions"][resolution].as_table()) {
    const toml::table copy = *preset;
    for (const auto& [k, v] : copy) setPath(root, std::string(k.str()), v);
    for (const std::string& o : overrides) applySet(root, o);
  }
  if (!keep_presets) {
    root.erase("resolution");
    root.erase("resolutions");
  }
  std::string out;
  writeToml(root, "", out);
  return out;
}

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

RunInfo infoOf(const Model& model, bool half) {
  RunInfo info;
  for (const Body& b : model.bodies) info.bodies.push_back({b.name, b.is_projectile});
  info.half = half;
  return info;
}

std::string timeDir(double t) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "t_%.6g", t);
  return buf;
}

}  // namespace

const char* Workbench::kFiles = "\x01files";

struct Workbench::Command {
  const char* name;
  const char* usage;
  const char* summary;
  const char* details;
  void (Workbench::*fn)(const std::vector<std::string>&);
};

const std::vector<Workbench::Command>& Workbench::table() {
  static const std::vector<Command> commands = {
      {"load", "load SCENE.toml | RUN_DIR", "load a scene, or a finished run folder to look at",
       "A scene is read and checked (not meshed yet); the changes made with `set` are dropped.\n"
       "A run folder (one with elements.pvd) can be rendered and plotted, not run.",
       &Workbench::load},
      {"show", "show [KEY ...]", "what is loaded and the run's state, or scene values",
       "Without a key: the scene, its changes, the run folder and the model's time and step.\n"
       "With keys: their values; a key that is a prefix shows everything under it\n"
       "(show bodies.0, show simulation). Arrays of tables count from 0.",
       &Workbench::show},
      {"set", "set KEY=VALUE ...", "change a scene value (TOML value, SI units)",
       "e.g. set simulation.end_time=20e-6 bodies.0.velocity=[0,0,-800]\n"
       "The scene is checked again at once. simulation.end_time applies to the running model\n"
       "(the run goes on); any other change rebuilds the model from t = 0 at the next command\n"
       "that needs it (and rewrites the output folder).",
       &Workbench::set},
      {"mesh", "mesh info", "mesh the scene (if not yet) and list bodies, elements, nodes, masses",
       "", &Workbench::meshInfo},
      {"run", "run [for T | to T]", "run to the end time, for a duration or to a time",
       "T in s, or with a unit: 5e-6, 5us, 0.01ms. Output is written at the scene's interval.\n"
       "The run stops at the first step that reaches T: steps are not shortened to land on it,\n"
       "so a run paused and continued takes the same steps as one run straight through.\n"
       "A time already passed is refused (going back: `restart` a checkpoint).\n"
       "Ctrl-C pauses the run after the current step and returns to the prompt; `run` or `step`\n"
       "continues from there. summary.toml then says paused, complete or failed.",
       &Workbench::run},
      {"step", "step [N]", "advance N steps (default 1)", "Ctrl-C pauses, as for run.",
       &Workbench::stepN},
      {"render", "render plate N [front|rear] [FIELD]", "draw plate N as it is now",
       "N counts the bodies that are not projectiles from 1, or is a body name. FIELD: damage\n"
       "(default), plastic_strain, von_mises, pressure, temperature, density, ...\n"
       "Both faces are written to RUN_FOLDER/shell/t_TIME/; the rear view outlines the holes.",
       &Workbench::render},
      {"plot", "plot velocity", "plot the projectile's velocity so far",
       "From the run's history.csv, to RUN_FOLDER/shell/velocity.png.", &Workbench::plot},
      {"probe", "probe", "projectile velocity and position, counts, energies",
       "Per projectile: mean velocity, centre of mass, nose (its most advanced point along the\n"
       "flight), residual velocity of the largest intact piece and how far its leading node\n"
       "(of a projectile made of particles: particle) is from the next plate's measuring\n"
       "plane. Then element, node and particle\n"
       "counts and the energy budget: the one the last step closed, at the step before (a\n"
       "step closes the budget of its start), as history.csv labels it.",
       &Workbench::probe},
      {"compare", "compare --image PHOTO --mm-per-px S [--plate N] [...]",
       "holes in a photograph of the tested plate against the plate now",
       "The options of `fesph compare` (`compare --help`): --center X,Y, --threshold T,\n"
       "--holes dark|bright, --face front|rear. Report, side-by-side and overlay images, CSV and\n"
       "JSON in RUN_FOLDER/shell/compare/.",
       &Workbench::compare},
      {"checkpoint", "checkpoint [FILE]", "save the model's full state (HDF5) to restart from it",
       "Default file: RUN_FOLDER/checkpoint_STEP.h5 (the scene's [output].checkpoints_kept\n"
       "newest are kept). The run also writes them at [output].checkpoint_interval.",
       &Workbench::checkpoint},
      {"restart", "restart [FILE] [--out DIR] [KEY=VALUE ...]", "go back to a saved state and go on from it",
       "Default FILE: the newest checkpoint of the current run folder. The scene is the one\n"
       "saved in the checkpoint; KEY=VALUE changes may move its end time. The series and\n"
       "histories of its run folder are cut back to the checkpoint and continued, as for\n"
       "`fesph run --restart`; refused while that folder holds a later checkpoint (it would\n"
       "lose its records). --out DIR goes on in DIR instead, with fresh series and histories.",
       &Workbench::restart},
      {"export", "export state [DIR] | export scene FILE", "write the current state or scene",
       "state: the model now as a ParaView series of one step (elements.pvd, particles.pvd) in\n"
       "DIR (default RUN_FOLDER/export/t_TIME). scene: the scene with its changes as TOML\n"
       "(comments dropped; msh paths and the material library are found from the new place).",
       &Workbench::exportCmd},
      {"report", "report [RUN_DIR ...] [--out DIR]", "the report of this run (fesph report)",
       "report.md: residual velocities against the scene's [reference], velocity histories,\n"
       "wall times, plate images and holes. Default: the current run folder; more run folders\n"
       "are compared with it. The run's summary.toml is written first (status complete,\n"
       "paused or failed). Default DIR: beside the first run folder, report/.",
       &Workbench::report},
      {"help", "help [COMMAND]", "list the commands, or explain one", "", &Workbench::help},
      {"quit", "quit", "leave the shell (also: exit, Ctrl-D)", "", &Workbench::quit},
      {"exit", "exit", "leave the shell", "", &Workbench::quit},
  };
  return commands;
}

std::vector<std::string> Workbench::commandNames() {
  std::vector<std::string> names;
  for (const Command& c : table()) names.push_back(c.name);
  return names;
}

Workbench::Workbench(ShellOptions options, std::atomic<bool>* stop, bool interactive)
    : options_(std::move(options)), stop_(stop), interactive_(interactive) {
  overrides_ = options_.overrides;
}

Workbench::~Workbench() = default;

bool Workbench::execute(const std::string& line) {
  stop_->store(false);  // a Ctrl-C while meshing for a run still pauses that run
  try {
    const std::vector<std::string> w = words(line);
    if (w.empty()) return true;
    for (const Command& c : table())
      if (w[0] == c.name) {
        (this->*c.fn)(std::vector<std::string>(w.begin() + 1, w.end()));
        return true;
      }
    throw UsageError("unknown command '" + w[0] + "'; `help` lists the commands");
  } catch (const Reported&) {
    // printed already
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
  }
  std::fflush(stderr);
  return false;
}

std::string Workbench::runFolder() const {
  if (session_) return session_->folder();
  if (!run_dir_.empty()) return run_dir_;
  if (scene_path_.empty()) throw UsageError("nothing loaded: `load SCENE.toml` or `load RUN_DIR`");
  const Scene s = loadScene(scene_path_, overrides_, options_.materials);
  return options_.out.empty() ? s.output.folder : options_.out;
}

bool Workbench::nothingRunYet() const {
  return !scene_path_.empty() && !(session_ && session_->outputStarted());
}

RunSession& Workbench::session() {
  if (scene_path_.empty())
    throw UsageError(run_dir_.empty() ? "no scene loaded: `load SCENE.toml` first"
                                      : "a run folder holds no model to run or probe; `restart` "
                                        "from one of its checkpoints or `load` its scene");
  if (!session_) {
    auto s = std::make_unique<RunSession>();
    // The folder's earlier run stays until this one writes: a probe or a look at the model
    // at t = 0 must not take a finished run's results away.
    s->open(scene_path_, overrides_, options_.out, options_.materials, &std::cout, true);
    session_ = std::move(s);
    std::printf("Model ready: %zu elements, %zu nodes, end time %.6g s, output in %s\n",
                session_->model().elems.size(), session_->model().nodes.size(),
                session_->endTime(), session_->folder().c_str());
  }
  return *session_;
}

std::vector<std::string> Workbench::sceneKeys() const {
  std::vector<std::string> keys;
  try {
    for (const auto& kv : sceneValues(scene_text_)) keys.push_back(kv.first);
  } catch (const InputError&) {
    // no completion from a scene that does not parse
  }
  return keys;
}

// ---- commands ------------------------------------------------------------------------------

void Workbench::load(const std::vector<std::string>& a) {
  if (a.size() != 1) throw UsageError("usage: load SCENE.toml | RUN_DIR");
  const std::string& path = a[0];
  if (fs::is_directory(path)) {
    if (!fs::exists(fs::path(path) / "elements.pvd"))
      throw UsageError(path + " is a folder without elements.pvd: not a run folder");
    session_.reset();
    scene_path_.clear();
    overrides_.clear();
    run_dir_ = path;
    const std::string text = readText(fs::path(path) / "scene.toml");
    try {
      // The scene as run: its changes and preset applied already (the preset holds the values
      // as run, so applying it again changes nothing).
      scene_text_ = text.empty() ? "" : sceneWithChanges(text, path + "/scene.toml", {});
    } catch (const InputError&) {
      scene_text_.clear();  // a copy that no longer parses: no values to show
    }
    const RunInfo info = readRunInfo(path);
    std::printf("Run folder %s: %zu bodies, %zu checkpoints (render, plot, compare; `restart` "
                "goes on from its newest checkpoint)\n",
                path.c_str(), info.bodies.size(), listCheckpoints(path).size());
    return;
  }
  // The command line's --set applies to the scene given on the command line only.
  std::vector<std::string> overrides = scene_path_.empty() && run_dir_.empty() ? overrides_
                                                                               : std::vector<std::string>{};
  const Scene s = loadScene(path, overrides, options_.materials);
  session_.reset();
  run_dir_.clear();
  scene_path_ = path;
  overrides_ = std::move(overrides);
  scene_text_ = sceneWithChanges(readText(path), path, overrides_);
  std::printf("Scene %s: \"%s\", %zu bodies, end time %.6g s, output every %.6g s\n",
              path.c_str(), s.title.c_str(), s.bodies.size(), s.controls.end_time,
              s.output.interval);
}

namespace {

/// Where a run folder's run stands, from its summary.toml: ": complete at t = 4e-06 s of
/// 4e-06 s, step 80"; empty when it has none (a run killed before its first output).
std::string runStanding(const std::string& dir) {
  const fs::path file = fs::path(dir) / "summary.toml";
  if (!fs::exists(file)) return "";
  try {
    const toml::table t = tomlcheck::parseFile(file.string());
    const auto status = t["status"].value<std::string>();
    const auto time = t["time"].value<double>(), end = t["end_time"].value<double>();
    const auto steps = t["steps"].value<long>();
    if (!status || !time || !end || !steps) return "";
    char text[160];
    std::snprintf(text, sizeof text, ": %s at t = %.6g s of %.6g s, step %ld",
                  standingStatus(dir, *status).c_str(), *time, *end, *steps);
    return text;
  } catch (const std::exception&) {  // an unreadable summary says nothing here
    return "";
  }
}

/// The session's state at its time as a run folder of one output step: its series (the
/// materials named by the scene's ids) and its scene.toml, in `dir`.
void writeState(const RunSession& s, const std::string& dir) {
  SeriesOptions options;
  options.material_names = s.scene().material_ids;
  SeriesWriter(dir, options).write(s.model(), s.model().time);
  std::ofstream(fs::path(dir) / "scene.toml") << s.scene().text;
}

}  // namespace

void Workbench::show(const std::vector<std::string>& a) {
  if (a.empty()) {
    if (!scene_path_.empty()) std::printf("scene      %s\n", scene_path_.c_str());
    if (!run_dir_.empty()) std::printf("run folder %s (no model)%s\n", run_dir_.c_str(),
                                       runStanding(run_dir_).c_str());
    if (scene_path_.empty() && run_dir_.empty()) std::printf("nothing loaded\n");
    for (const std::string& o : overrides_) std::printf("changed    %s\n", o.c_str());
    if (session_) {
      const Model& m = session_->model();
      std::printf("model      t = %.6g s of %.6g s, step %ld, dt %.4g s (%s)%s\n", m.time,
                  session_->endTime(), m.step, m.dt,
                  m.dt_limiter.empty() ? "-" : m.dt_limiter.c_str(),
                  !session_->failure().empty() ? ", FAILED"
                  : session_->complete()       ? ", complete"
                                               : "");
      std::printf("output     %s\n", session_->folder().c_str());
    } else if (!scene_path_.empty()) {
      std::printf("model      not built yet (the next run, step, mesh info or probe builds it)\n");
    }
    return;
  }
  const auto by_name = sceneValues(scene_text_), by_index = sceneValues(scene_text_, true);
  if (by_name.empty()) throw UsageError("no scene values: nothing loaded");
  for (const std::string& key : a) {
    bool found = false;
    for (const auto* values : {&by_name, &by_index}) {
      for (const auto& [k, v] : *values)
        if (k == key || k.rfind(key + ".", 0) == 0) {
          std::printf("%s = %s\n", k.c_str(), v.c_str());
          found = true;
        }
      if (found) break;
    }
    if (!found) throw UsageError("no scene key '" + key + "' (tab completes the keys)");
  }
}

void Workbench::set(const std::vector<std::string>& a) {
  if (a.empty()) throw UsageError("usage: set KEY=VALUE ...");
  if (scene_path_.empty())
    throw UsageError(run_dir_.empty() ? "no scene loaded" : "a run folder cannot be changed; load a scene");
  std::vector<std::string> next = overrides_;
  std::vector<std::string> keys;
  for (const std::string& kv : a) {
    const std::size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == kv.size())
      throw UsageError("'" + kv + "' is not KEY=VALUE");
    const std::string key = kv.substr(0, eq);
    next.erase(std::remove_if(next.begin(), next.end(),
                              [&](const std::string& o) { return o.rfind(key + "=", 0) == 0; }),
               next.end());
    next.push_back(kv);
    keys.push_back(key);
  }
  const Scene s = loadScene(scene_path_, next, options_.materials);  // throws: nothing changes
  overrides_ = std::move(next);
  scene_text_ = sceneWithChanges(readText(scene_path_), scene_path_, overrides_);
  const bool only_end_time =
      std::all_of(keys.begin(), keys.end(), [](const std::string& k) { return k == "simulation.end_time"; });
  if (session_ && only_end_time && s.controls.end_time > session_->model().time &&
      session_->failure().empty()) {
    session_->model().controls.end_time = s.controls.end_time;
    std::printf("end time %.6g s: the run goes on from t = %.6g s\n", s.controls.end_time,
                session_->model().time);
    return;
  }
  for (const std::string& kv : a) std::printf("%s\n", kv.c_str());
  if (session_ && session_->model().step > 0)
    std::printf("The model is rebuilt from t = 0 at the next run, which replaces the run in %s: "
                "its series, histories, checkpoints and images (a checkpoint saved elsewhere "
                "stays)\n",
                session_->folder().c_str());
  session_.reset();
}

void Workbench::meshInfo(const std::vector<std::string>& a) {
  if (a.size() != 1 || a[0] != "info") throw UsageError("usage: mesh info");
  const RunSession& s = session();
  const Model& m = s.model();
  const auto materialOf = [&](const Body& body) {  // "steel_4340+OFHC_copper": several volumes
    const SceneBody& sb = s.scene().bodies.at(static_cast<std::size_t>(&body - m.bodies.data()));
    std::string ids = sb.material;
    for (std::size_t v = 1; v < sb.volume_materials.size(); ++v) {
      const auto& all = sb.volume_materials;
      if (std::find(all.begin(), all.begin() + static_cast<long>(v), all[v]) ==
          all.begin() + static_cast<long>(v))
        ids += "+" + all[v];
    }
    return ids;
  };
  // columns as wide as their longest entry (a material id such as OFHC_copper)
  int name_width = 14, material_width = 10;
  for (const Body& body : m.bodies) {
    name_width = std::max(name_width, static_cast<int>(body.name.size()));
    material_width = std::max(material_width, static_cast<int>(materialOf(body).size()));
  }
  std::printf("%-*s %-*s %-10s %9s %9s %11s  %s\n", name_width, "body", material_width,
              "material", "kind", "elements", "nodes", "mass (kg)", "extent x, y, z (mm)");
  for (std::size_t b = 0; b < m.bodies.size(); ++b) {
    const Body& body = m.bodies[b];
    const auto [lo, hi] = bodyExtent(m, static_cast<int>(b));
    const Vec3 size = lo.x() <= hi.x() ? Vec3(hi - lo) : Vec3::Zero();
    const char* kind = body.is_projectile                               ? "projectile"
                       : body.discretisation == Discretisation::Sph ? "particles"
                                                                    : "target";
    std::printf("%-*s %-*s %-10s %9zu %9zu %11.5g  %.2f x %.2f x %.2f%s\n", name_width,
                body.name.c_str(), material_width, materialOf(body).c_str(), kind,
                body.elem_end - body.elem_begin, body.node_end - body.node_begin,
                bodyMass(m, static_cast<int>(b)), size.x() * 1e3, size.y() * 1e3, size.z() * 1e3,
                body.discretisation == Discretisation::Sph ? " (its particles' centres)" : "");
  }
  std::printf("total: %zu elements, %zu nodes, %zu particles%s\n", m.elems.size(), m.nodes.size(),
              m.particles.size(), s.scene().half ? "; half model (symmetry plane y = 0)" : "");
}

void Workbench::advance(double until, long steps) {
  RunSession& s = session();
  if (!s.failure().empty())
    throw RunError("the run failed earlier (" + s.failure() +
                   "); `set` a change or `load` the scene again to start over");
  if (s.complete()) {
    std::printf("The run is at its end time, t = %.6g s; `set simulation.end_time=...` to go on\n",
                s.model().time);
    return;
  }
  Progress progress(s.endTime(), interactive_);
  s.onStep([&](const Model& m) { progress.update(m.time, m.step, m.dt); });
  const StopReason why = s.advance(until, steps, stop_);
  s.onStep(nullptr);
  progress.finish();
  writeStatus();
  const Model& m = s.model();
  switch (why) {
    case StopReason::EndTime:
      std::printf("End time reached: t = %.6g s, step %ld\n", m.time, m.step);
      s.printSummary();
      break;
    case StopReason::Limit:
      std::printf("t = %.6g s, step %ld, dt = %.4g s (%s)\n", m.time, m.step, m.dt,
                  m.dt_limiter.c_str());
      break;
    case StopReason::Interrupted:
      std::printf("Paused (Ctrl-C) at t = %.6g s, step %ld; `run` or `step` goes on\n", m.time,
                  m.step);
      break;
    case StopReason::Failed:
      throw RunError("the run stopped at t = " + seconds(m.time) + ", step " +
                     std::to_string(m.step) + ": " + s.failure() + "\nThe output so far is valid and kept in " +
                     s.folder());
  }
}

void Workbench::run(const std::vector<std::string>& a) {
  if (a.empty()) return advance(1e300, -1);
  if (a.size() == 2 && (a[0] == "for" || a[0] == "to")) {
    const double t = parseTime(a[1]);
    RunSession& s = session();
    if (a[0] == "for" && !(t > 0)) throw UsageError("run for T: T must be > 0");
    const double now = s.model().time;
    // Without this the run took no step and printed where it stood, as if it had got there.
    if (a[0] == "to" && !(t > now) && !s.complete())
      throw UsageError("run to " + a[1] + ": the model is at t = " + seconds(now) +
                       " already; `run to` a later time (going back: `restart` a checkpoint)");
    return advance(a[0] == "for" ? now + t : t, -1);
  }
  throw UsageError("usage: run [for T | to T]");
}

void Workbench::stepN(const std::vector<std::string>& a) {
  long n = 1;
  if (a.size() > 1) throw UsageError("usage: step [N]");
  if (a.size() == 1 && (!readNumber(a[0], n) || n < 1))
    throw UsageError("step N: N must be a whole number >= 1");
  advance(1e300, n);
}

void Workbench::render(const std::vector<std::string>& a) {
  if (a.size() < 2 || a[0] != "plate" || a.size() > 4)
    throw UsageError("usage: render plate N [front|rear] [FIELD]");
  bool rear = false;
  ImageOptions o;
  o.width = 1200;
  o.height = 900;
  for (std::size_t k = 2; k < a.size(); ++k) {
    if (a[k] == "front" || a[k] == "rear")
      rear = a[k] == "rear";
    else
      o.field = a[k];
  }
  RunInfo info;
  double time = 0;
  const std::string source = currentState(info, time);
  const int body = plateBody(info, a[1]);
  const std::string out = (fs::path(runFolder()) / "shell" / timeDir(time)).string();
  const std::vector<PlateImages> images = renderPlateImages(source, -1, o, out, {body});
  if (images.empty())
    throw RunError("plate '" + info.bodies[static_cast<std::size_t>(body)].name +
                   "' has neither elements nor particles at t = " + shortestText(time) + " s");
  for (const PlateImages& p : images) {
    std::printf("%s\n", (rear ? p.rear_png : p.front_png).c_str());
    std::printf("  plate '%s' at t = %.6g s: %zu through-hole%s", p.plate.c_str(), p.time,
                p.holes.holes.size(), p.holes.holes.size() == 1 ? "" : "s");
    for (std::size_t k = 0; k < p.holes.holes.size(); ++k)
      std::printf("%s%.2f", k ? ", " : " (equivalent diameter ", p.holes.holes[k].diameter * 1e3);
    std::printf("%s; the other face: %s\n", p.holes.holes.empty() ? "" : " mm)",
                (rear ? p.front_png : p.rear_png).c_str());
  }
}

std::string Workbench::currentState(RunInfo& info, double& time) {
  if (!scene_path_.empty()) {
    RunSession& s = session();
    const std::string dir = (fs::path(s.folder()) / "shell" / "state").string();
    writeState(s, dir);
    info = infoOf(s.model(), s.scene().half);
    time = s.model().time;
    return dir;
  }
  if (run_dir_.empty()) throw UsageError("nothing loaded: `load SCENE.toml` or `load RUN_DIR`");
  info = readRunInfo(run_dir_);
  time = render_detail::readRunStep(run_dir_, -1).time;
  return run_dir_;
}

void Workbench::compare(const std::vector<std::string>& a) {
  CompareCommandOptions o;
  CLI::App cmd{"compare: holes in a photograph against the plate as it is now", "compare"};
  addCompareOptions(cmd, o);
  std::vector<std::string> args(a.rbegin(), a.rend());  // CLI11 takes them last first
  try {
    cmd.parse(args);
  } catch (const CLI::CallForHelp&) {
    std::printf("%s", cmd.help().c_str());
    return;
  } catch (const CLI::ParseError& e) {
    throw UsageError(std::string(e.what()) + "; `compare --help` lists the options");
  }
  RunInfo info;
  double time = 0;
  o.run_dir = currentState(info, time);
  if (o.out.empty()) o.out = (fs::path(runFolder()) / "shell" / "compare").string();
  if (compareCommand(o) != 0) throw Reported();
}

void Workbench::plot(const std::vector<std::string>& a) {
  if (a.size() != 1 || a[0] != "velocity") throw UsageError("usage: plot velocity");
  const fs::path folder = runFolder();
  if (nothingRunYet()) throw UsageError("nothing has run yet: `run` or `step` first");
  const std::string png = (folder / "shell" / "velocity.png").string();
  fs::create_directories(folder / "shell");
  std::printf("%s\n", renderVelocityPlot({{folder.filename().string(), (folder / "history.csv").string()}},
                                         "", png)
                          .c_str());
}

void Workbench::probe(const std::vector<std::string>& a) {
  if (!a.empty()) throw UsageError("usage: probe");
  const Model& m = session().model();
  std::printf("t = %.6g s, step %ld, dt %.4g s (%s)\n", m.time, m.step, m.dt,
              m.dt_limiter.empty() ? "-" : m.dt_limiter.c_str());
  for (std::size_t b = 0; b < m.bodies.size(); ++b) {
    const Body& body = m.bodies[b];
    if (!body.is_projectile) continue;
    const Vec3 v = bodyMeanVelocity(m, static_cast<int>(b));
    // Its plates; none for all but the first after a restart from a checkpoint of format 13
    // or older (their projectiles are not tracked).
    const PlateCrossings* crossings = session().crossingsOf(static_cast<int>(b));
    const std::vector<PlateCrossing> plates =
        crossings ? crossings->plates() : std::vector<PlateCrossing>{};
    // Centre of mass, and the nose: the most advanced point along the flight, on the axis
    // through the centre of mass.
    double mass = 0;
    Vec3 c = Vec3::Zero();
    const Vec3 dir = v.norm() > 0 ? Vec3(v.normalized()) : Vec3(-Vec3::UnitZ());
    double lead = -1e300;
    const auto add = [&](const Vec3& x, double mi) {
      mass += mi;
      c += mi * x;
      lead = std::max(lead, x.dot(dir));
    };
    for (std::size_t n = body.node_begin; n < body.node_end; ++n)
      if (m.nodes.m[n] > 0) add(m.nodes.x[n], m.nodes.m[n]);
    for (std::size_t p = 0; p < m.particles.size(); ++p)
      if (m.particles.body[p] == static_cast<int>(b)) add(m.particles.x[p], m.particles.m[p]);
    if (mass > 0) c /= mass;
    const Vec3 nose_at = c + (lead - c.dot(dir)) * dir;
    std::printf("projectile '%s'\n", body.name.c_str());
    std::printf("  velocity        (%.2f, %.2f, %.2f) m/s, |v| %.2f m/s\n", v.x(), v.y(), v.z(), v.norm());
    std::printf("  centre of mass  (%.3f, %.3f, %.3f) mm%s\n", c.x() * 1e3, c.y() * 1e3, c.z() * 1e3,
                session().scene().half ? " (of the modelled half; mass too)" : "");
    std::printf("  nose            (%.3f, %.3f, %.3f) mm\n", nose_at.x() * 1e3, nose_at.y() * 1e3,
                nose_at.z() * 1e3);
    std::printf("  mass            %.6g kg\n", mass);
    if (m.bodies.size() > 1) {
      const ResidualVelocity r = residualVelocity(m, static_cast<int>(b));
      std::printf("  residual        %.2f m/s (largest intact piece, %.1f %% of the mass; %s)\n", r.speed,
                  100 * r.mass_fraction, session().clearance(static_cast<int>(b), r));
      // How far the piece's leading node still is from its next measuring plane.
      for (const PlateCrossing& p : plates) {
        if (p.t_measured >= 0) continue;
        const std::vector<Piece> pieces = bodyPieces(m, static_cast<int>(b));
        if (pieces.empty()) break;
        std::printf("  piece's lead    %.3f mm before the measuring plane of '%s' (v_k not yet taken)\n",
                    (p.measure_depth - leadingDepth(m, p, pieces[0])) * 1e3, p.name.c_str());
        break;
      }
    }
    // Where its material is: a projectile that breaks up leaves its debris at the plates.
    const std::vector<MaterialRegion> regions =
        materialByRegion(m, plates, static_cast<int>(b));
    if (!regions.empty())
      std::printf("  where it is     region: live nodes g (v along the flight m/s) | particles g "
                  "(v m/s, mean distance from the shot line mm)\n");
    const Vec3 n = regions.empty() ? Vec3::Zero() : plates[0].normal;
    for (const MaterialRegion& g : regions) {
      if (g.nodes.mass == 0 && g.particles.mass == 0) continue;
      char nodes[64] = "-", particles[64] = "-";
      if (g.nodes.mass > 0)
        std::snprintf(nodes, sizeof nodes, "%.4f (%.1f)", 1e3 * g.nodes.mass,
                      -g.nodes.velocity.dot(n));
      if (g.particles.mass > 0)
        std::snprintf(particles, sizeof particles, "%.4f (%.1f, %.1f)", 1e3 * g.particles.mass,
                      -g.particles.velocity.dot(n), 1e3 * g.particle_offset);
      std::printf("    %-24s %-22s | %s\n", g.name.c_str(), nodes, particles);
    }
  }
  const ConversionStats& cs = m.conversion;
  std::printf("elements        %zu (live %zu, eroded %ld, converted %ld)\n", m.elems.size(),
              m.elems.size() - static_cast<std::size_t>(cs.eroded + cs.converted), cs.eroded,
              cs.converted);
  std::printf("nodes           %zu\nparticles       %zu\n", m.nodes.size(), m.particles.size());
  const EnergyBudget& e = m.energy;
  std::printf("energy (J)      kinetic %.6g  internal %.6g (plastic work %.6g)  contact %.6g  "
              "eroded %.6g  conversion %.6g\n",
              e.kinetic, e.internal, e.plastic_work, e.contact, e.eroded, e.conversion);
  std::printf("                total %.6g of the initial %.6g, balance error %.3g %%\n", e.total(),
              e.initial, 100 * e.balanceError());
  if (!m.symmetry.empty())
    std::printf("                %s\n", kModelledPart);
  // The budget at t^n is closed by the step from t^n: say so where it is not now's.
  if (e.step != m.step)
    std::printf("                (at t = %.6g s, step %ld: a step closes the budget of its start, "
                "as in history.csv)\n",
                e.time, e.step);
}

void Workbench::checkpoint(const std::vector<std::string>& a) {
  if (a.size() > 1) throw UsageError("usage: checkpoint [FILE]");
  RunSession& s = session();
  std::string path;
  if (a.empty()) {
    path = s.checkpoint();
  } else {
    path = a[0];
    s.checkpoint(path);
  }
  std::printf("%s (t = %.6g s, step %ld); `restart %s` comes back to it\n", path.c_str(),
              s.model().time, s.model().step, path.c_str());
}

void Workbench::restart(const std::vector<std::string>& a) {
  const char* usage = "usage: restart [FILE] [--out DIR] [KEY=VALUE ...]";
  std::string path, out;
  std::vector<std::string> changes;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k] == "--out" && k + 1 < a.size() && out.empty())
      out = a[++k];
    else if (a[k].find('=') != std::string::npos)
      changes.push_back(a[k]);
    else if (path.empty() && a[k] != "--out")
      path = a[k];
    else
      throw UsageError(usage);
  }
  if (path.empty()) {  // the newest checkpoint of the current run
    const std::vector<std::string> saved = listCheckpoints(runFolder());
    if (saved.empty()) throw UsageError("no checkpoint in " + runFolder() + "; `restart FILE`");
    path = saved.back();
  }
  auto s = std::make_unique<RunSession>();
  s->restart(path, changes, out, &std::cout);
  // The scene is the one saved in the checkpoint, with its --set changes; its text is the
  // scene as run, changes and preset applied (as a run folder's, see load).
  const Scene& sc = s->scene();
  overrides_ = sc.overrides;
  scene_text_ = sceneWithChanges(sc.text, sc.path, {});
  scene_path_ = sc.path;
  run_dir_.clear();
  session_ = std::move(s);
  std::printf("Restarted at t = %.6g s, step %ld of %.6g s; output continues in %s\n",
              session_->model().time, session_->model().step, session_->endTime(),
              session_->folder().c_str());
}

void Workbench::exportCmd(const std::vector<std::string>& a) {
  if (!a.empty() && a[0] == "scene" && a.size() == 2) {
    if (scene_path_.empty()) throw UsageError("no scene loaded");
    std::ofstream out(a[1], std::ios::trunc);
    out << "# " << scene_path_ << " with the changes made in fesph shell and its resolution "
        << "preset applied (comments dropped)\n";
    for (const std::string& o : overrides_) out << "#   " << o << "\n";
    out << sceneWithChanges(readText(scene_path_), scene_path_, overrides_, false);
    if (!out) throw RunError("cannot write " + a[1]);
    std::printf("%s\n", a[1].c_str());
    return;
  }
  if (!a.empty() && a[0] == "state" && a.size() <= 2) {
    RunSession& s = session();
    const std::string dir = a.size() == 2 ? a[1]
                                          : (fs::path(s.folder()) / "export" / timeDir(s.model().time)).string();
    writeState(s, dir);
    std::printf("%s/elements.pvd, %s/particles.pvd (t = %.6g s)\n", dir.c_str(), dir.c_str(),
                s.model().time);
    return;
  }
  throw UsageError("usage: export state [DIR] | export scene FILE");
}

void Workbench::report(const std::vector<std::string>& a) {
  ReportOptions o;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k] == "--out" && k + 1 < a.size())
      o.out = a[++k];
    else if (a[k].rfind("--", 0) == 0)
      throw UsageError("usage: report [RUN_DIR ...] [--out DIR]");
    else
      o.run_dirs.push_back(a[k]);
  }
  if (o.run_dirs.empty()) {
    if (nothingRunYet())
      throw UsageError("nothing has run yet: `run` or `step` first, or give RUN_DIR");
    o.run_dirs.push_back(runFolder());
  }
  writeStatus();
  if (reportCommand(o) != 0) throw Reported();
}

void Workbench::writeStatus() const {
  // summary.toml says where the shell's run stands, for `fesph report` and a reader of the
  // folder; without it the folder kept the "running" of its last field output.
  if (!session_ || !session_->outputStarted()) return;
  const RunSession& s = *session_;
  s.writeSummary(s.folder() + "/summary.toml", !s.failure().empty() ? "failed"
                                               : s.complete()        ? "complete"
                                                                     : "paused");
}

void Workbench::help(const std::vector<std::string>& a) {
  if (a.empty()) {
    for (const Command& c : table()) std::printf("  %-40s %s\n", c.usage, c.summary);
    std::printf("Tab completes commands, scene keys and file names; `help COMMAND` explains one.\n");
    return;
  }
  for (const Command& c : table())
    if (a[0] == c.name) {
      std::printf("%s\n  %s\n", c.usage, c.summary);
      if (*c.details) {
        std::istringstream lines(c.details);
        for (std::string l; std::getline(lines, l);) std::printf("  %s\n", l.c_str());
      }
      return;
    }
  throw UsageError("no command '" + a[0] + "'; `help` lists the commands");
}

void Workbench::quit(const std::vector<std::string>&) { done_ = true; }

// ---- completion ----------------------------------------------------------------------------

std::vector<std::string> Workbench::completions(const std::vector<std::string>& before,
                                                const std::string& word) const {
  std::vector<std::string> all;
  const std::size_t n = before.size();
  const std::string cmd = n ? before[0] : "";
  if (n == 0) {
    all = commandNames();
  } else if (cmd == "help" && n == 1) {
    all = commandNames();
  } else if (cmd == "load") {
    return {kFiles};
  } else if (cmd == "set") {
    for (const std::string& k : sceneKeys()) all.push_back(k + "=");
  } else if (cmd == "show") {
    all = sceneKeys();
  } else if (cmd == "mesh" && n == 1) {
    all = {"info"};
  } else if (cmd == "run" && n == 1) {
    all = {"for", "to"};
  } else if (cmd == "plot" && n == 1) {
    all = {"velocity"};
  } else if (cmd == "export" && n == 1) {
    all = {"state", "scene"};
  } else if (cmd == "compare" && n >= 2 && before[n - 1] == "--image") {
    return {kFiles};
  } else if (cmd == "compare" && n >= 2 && (before[n - 1] == "--holes")) {
    all = {"dark", "bright"};
  } else if (cmd == "compare" && n >= 2 && (before[n - 1] == "--face")) {
    all = {"front", "rear"};
  } else if (cmd == "compare") {
    all = {"--image", "--mm-per-px", "--plate", "--center", "--threshold", "--holes", "--face", "--out"};
  } else if (cmd == "export" || cmd == "checkpoint" || cmd == "restart") {
    return {kFiles};
  } else if (cmd == "render" && n == 1) {
    all = {"plate"};
  } else if (cmd == "render" && n == 2) {
    if (session_)
      for (const Body& b : session_->model().bodies)
        if (!b.is_projectile) all.push_back(b.name);
    if (!run_dir_.empty())
      for (const RunBody& b : readRunInfo(run_dir_).bodies)
        if (!b.projectile) all.push_back(b.name);
  } else if (cmd == "render" && n >= 3) {
    all = {"front", "rear"};
    for (const std::string& f : SeriesWriter::elementFields()) all.push_back(f);
  }
  std::vector<std::string> out;
  for (const std::string& c : all)
    if (c.rfind(word, 0) == 0) out.push_back(c);
  return out;
}

}  // namespace fesph
