#include "granpack/io/report.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "granpack/core/error.h"
#include "granpack/io/atomic_file.h"

namespace granpack {

namespace {
template <class T> nlohmann::json opt(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
/// wall_split's keys (docs/report.md) and the parts they hold, for the writer and the reader.
constexpr std::pair<const char*, double WallSplit::*> kWallSplitKeys[] = {
    {"forces", &WallSplit::forces}, {"neighbor", &WallSplit::neighbor},
    {"comm", &WallSplit::comm},     {"integrate", &WallSplit::integrate},
    {"io", &WallSplit::io},         {"event_driven", &WallSplit::event_driven},
    {"other", &WallSplit::other}};

nlohmann::json stage_json(const StageReport& s) {
  nlohmann::json e;
  e["name"] = s.name;
  e["kind"] = s.kind;
  e["steps"] = s.steps;
  e["time"] = s.time;
  e["equilibrated"] = opt(s.equilibrated);
  e["phi"] = opt(s.phi);
  e["pressure"] = opt(s.pressure);
  e["kappa"] = opt(s.kappa);
  e["inertia_max"] = opt(s.inertia_max);
  e["z"] = opt(s.z);
  e["z_star"] = opt(s.z_star);
  e["x0"] = opt(s.x0);
  e["x2"] = opt(s.x2);
  e["z2"] = opt(s.z2);
  nlohmann::json values = nlohmann::json::object();
  for (const auto& [key, value] : s.values)
    values[key] = value;
  e["values"] = values;
  if (!s.levels.empty()) {
    e["levels"] = nlohmann::json::array();
    for (const auto& l : s.levels)
      e["levels"].push_back(stage_json(l));
  }
  e["wall_seconds"] = s.wall_seconds;
  if (const auto& t = s.phase_seconds)
    e["phase_seconds"] = {{"forces", t->forces},
                          {"neighbor", t->neighbor},
                          {"comm", t->comm},
                          {"integrate", t->integrate},
                          {"forces_slowest_rank", t->forces_slowest},
                          {"forces_cpu", t->forces_cpu},
                          {"forces_cpu_slowest_rank", t->forces_cpu_slowest},
                          {"force_imbalance", t->force_imbalance()}};
  if (const auto& w = s.wall_split)
    for (const auto& [key, part] : kWallSplitKeys)
      e["wall_split"][key] = (*w).*part;
  if (const auto& m = s.md_classes) {
    auto one = [](const StepClass& c) {
      return nlohmann::json{{"steps", c.steps},
                            {"particle_steps", c.particle_steps},
                            {"seconds", c.seconds},
                            {"particle_steps_per_second", opt(c.rate())}};
    };
    e["md_classes"] = {{"dense_contacts_per_grain", m->threshold},
                       {"dense", one(m->dense)},
                       {"loose", one(m->loose)}};
  }
  return e;
}
template <class T> std::optional<T> opt_from(const nlohmann::json& e, const char* key) {
  if (!e.contains(key) || e[key].is_null())
    return std::nullopt;
  return e[key].get<T>();
}
StageReport stage_from_json(const nlohmann::json& e) {
  StageReport s;
  s.name = e.at("name").get<std::string>();
  s.kind = e.at("kind").get<std::string>();
  s.steps = e.at("steps").get<std::int64_t>();
  s.time = e.at("time").get<double>();
  s.equilibrated = opt_from<bool>(e, "equilibrated");
  s.phi = opt_from<double>(e, "phi");
  s.pressure = opt_from<double>(e, "pressure");
  s.kappa = opt_from<double>(e, "kappa");
  s.inertia_max = opt_from<double>(e, "inertia_max");
  s.z = opt_from<double>(e, "z");
  s.z_star = opt_from<double>(e, "z_star");
  s.x0 = opt_from<double>(e, "x0");
  s.x2 = opt_from<double>(e, "x2");
  s.z2 = opt_from<double>(e, "z2");
  for (const auto& [key, value] : e.at("values").items())
    s.values.emplace_back(key, value.get<double>());
  if (e.contains("levels"))
    for (const auto& l : e["levels"])
      s.levels.push_back(stage_from_json(l));
  s.wall_seconds = e.at("wall_seconds").get<double>();
  if (e.contains("phase_seconds")) {
    const auto& t = e["phase_seconds"];
    PhaseSeconds p;
    p.forces = t.at("forces").get<double>();
    p.neighbor = t.at("neighbor").get<double>();
    p.comm = t.at("comm").get<double>();
    p.integrate = t.at("integrate").get<double>();
    p.forces_slowest = t.at("forces_slowest_rank").get<double>();
    p.forces_cpu = t.at("forces_cpu").get<double>();
    p.forces_cpu_slowest = t.at("forces_cpu_slowest_rank").get<double>();
    s.phase_seconds = p;
  }
  // Absent in files and checkpoints written before they were added.
  if (e.contains("wall_split")) {
    WallSplit w;
    for (const auto& [key, part] : kWallSplitKeys)
      w.*part = e["wall_split"].at(key).get<double>();
    s.wall_split = w;
  }
  if (e.contains("md_classes")) {
    const auto& t = e["md_classes"];
    auto one = [](const nlohmann::json& c) {
      StepClass k;
      k.steps = c.at("steps").get<std::int64_t>();
      k.particle_steps = c.at("particle_steps").get<std::int64_t>();
      k.seconds = c.at("seconds").get<double>();
      return k;
    };
    s.md_classes = StepClasses{t.at("dense_contacts_per_grain").get<double>(), one(t.at("dense")),
                               one(t.at("loose"))};
  }
  return s;
}
} // namespace

std::string stage_report_json(const StageReport& s) {
  return stage_json(s).dump();
}

StageReport stage_report_from_json(const std::string& text) {
  try {
    return stage_from_json(nlohmann::json::parse(text));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("a stage entry of the checkpoint is not valid: ") + e.what());
  }
}

std::string to_json(const RunReport& r) {
  nlohmann::json j;
  j["version"] = r.version;
  j["build"] = {{"commit", r.build_commit}, {"dirty", r.build_dirty}};
  j["dimension"] = r.dimension;
  j["n"] = r.n;
  j["ranks"] = r.ranks;
  j["deck"] = r.deck;
  j["final"] = r.final_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.final_file);
  j["wall_seconds"] = r.wall_seconds;
  j["stages"] = nlohmann::json::array();
  for (const auto& s : r.stages)
    j["stages"].push_back(stage_json(s));
  return j.dump(2) + "\n";
}

void write_text_atomically(const std::filesystem::path& path, const std::string& text) {
  const auto tmp = temp_path_for(path);
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::trunc | std::ios::binary);
    out << text;
    out.close();
    if (!out) {
      const int e = errno; // set by the failed write or close (ENOSPC, EDQUOT, EFBIG)
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw WriteError("cannot write " + path.string() + ": " +
                       (e ? std::strerror(e) : "write failed") + "; " + tmp.filename().string() +
                       " was removed");
    }
  }
  commit_temp_file(tmp, path);
}

void write_report(const std::filesystem::path& path, const RunReport& r) {
  write_text_atomically(path, to_json(r));
}

} // namespace granpack
