// SPDX-License-Identifier: MIT
#include "core/io/history_csv.hpp"

#include "core/common/error.hpp"
#include "core/io/replace_file.hpp"
#include "core/state/model_build.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace fesph {

HistoryCsv::HistoryCsv(const std::string& path, const Model& model)
    : path_(path), out_(path, std::ios::trunc) {
  if (!out_) throw RunError("cannot write history file " + path);
  out_ << "time,step,dt,kinetic,internal,plastic_work,bulk_viscosity,contact,eroded,conversion,"
          "total,balance_error,momentum_x,momentum_y,momentum_z,eroded_elements,eroded_mass,"
          "converted_elements,particles";
  for (const Body& b : model.bodies)
    out_ << ',' << b.name << "_vx," << b.name << "_vy," << b.name << "_vz";
  out_ << '\n';
  out_.flush();
}

HistoryCsv::HistoryCsv(const std::string& path, std::size_t rows) : path_(path) {
  std::ifstream in(path);
  if (!in) throw RunError("cannot read history file " + path + " to continue it");
  std::string kept, line;
  std::size_t lines = 0;
  while (lines < rows + 1 && std::getline(in, line)) {
    kept += line + '\n';
    ++lines;
  }
  in.close();
  if (lines < rows + 1)
    throw RunError(path + ": " + std::to_string(lines ? lines - 1 : 0) + " rows, the checkpoint "
                   "expects " + std::to_string(rows));
  if (rows > 0) {  // the last row kept: time,step,...
    const std::size_t row = kept.rfind('\n', kept.size() - 2) + 1;
    last_row_ = kept.substr(row, kept.size() - 1 - row);
  }
  replaceFile(path, kept);
  out_.open(path, std::ios::app);
  if (!out_) throw RunError("cannot write history file " + path);
}

std::string HistoryCsv::timeText(double time) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", time);
  return buf;
}

bool HistoryCsv::endsAt(double time) const {
  const std::string t = timeText(time);
  return last_row_.size() > t.size() && last_row_.compare(0, t.size(), t) == 0 &&
         last_row_[t.size()] == ',';
}

std::string HistoryCsv::row(const std::string& path, std::size_t n) {
  std::ifstream in(path);
  std::string line;
  for (std::size_t k = 0; k <= n; ++k)  // the header, then n rows
    if (!std::getline(in, line)) return "";
  return line;
}

void HistoryCsv::record(const Model& model) {
  const EnergyBudget& en = model.energy;
  char buf[64];
  std::string& row = last_row_;
  auto put = [&](double x) {
    std::snprintf(buf, sizeof buf, ",%.10g", x);
    row += buf;
  };
  auto count = [&](long long n) { row += ',' + std::to_string(n); };
  row = timeText(en.time);
  row += ',' + std::to_string(en.step);
  for (double x : {model.dt, en.kinetic, en.internal, en.plastic_work, en.bulk_viscosity,
                   en.contact, en.eroded, en.conversion, en.total(), en.balanceError(),
                   en.momentum.x(), en.momentum.y(), en.momentum.z()})
    put(x);
  count(model.conversion.eroded);
  put(model.conversion.eroded_mass);
  count(model.conversion.converted);
  count(static_cast<long long>(model.particles.size()));
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const Vec3 v = bodyMeanVelocity(model, static_cast<int>(b));
    put(v.x());
    put(v.y());
    put(v.z());
  }
  out_ << row << '\n';
  out_.flush();
}

}  // namespace fesph
