#include "granpack/app/ensemble_summary.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>

#include "granpack/app/analyze.h"
#include "granpack/app/density_fit_json.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/core/error.h"
#include "granpack/io/report.h"

namespace granpack {

namespace {

using json = nlohmann::json;

bool is_number(const json& v) {
  return v.is_number() && !v.is_boolean();
}

std::string escape(const std::string& key) {
  std::string out;
  for (char c : key)
    out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

/// Leaves of a document by JSON pointer: numbers, and numeric arrays kept whole (curves).
void flatten(const json& v, const std::string& at, std::map<std::string, json>& out) {
  if (v.is_object()) {
    for (const auto& [k, x] : v.items())
      flatten(x, at + "/" + escape(k), out);
  } else if (v.is_array()) {
    const bool curve = !v.empty() && std::all_of(v.begin(), v.end(), is_number);
    if (curve) {
      out[at] = v;
    } else {
      for (std::size_t i = 0; i < v.size(); ++i)
        flatten(v[i], at + "/" + std::to_string(i), out);
    }
  } else if (is_number(v)) {
    out[at] = v;
  }
}

/// The commit a sample's report names ("+dirty" when built with uncommitted changes), or
/// "unrecorded" for reports written before builds were recorded.
std::string build_of(const json& report) {
  if (!report.contains("build") || !report["build"].is_object() ||
      !report["build"].contains("commit") || !report["build"]["commit"].is_string())
    return "unrecorded";
  std::string c = report["build"]["commit"].get<std::string>();
  if (report["build"].value("dirty", false))
    c += "+dirty";
  return c;
}

/// report.json with its list of stages keyed by stage name, which stays meaningful when a
/// deck gains a stage ("/stages/compress/phi", not "/stages/2/phi").
json stages_by_name(json report) {
  if (!report.contains("stages") || !report["stages"].is_array())
    return report;
  json named = json::object();
  for (std::size_t i = 0; i < report["stages"].size(); ++i) {
    const json& st = report["stages"][i];
    std::string name = st.contains("name") && st["name"].is_string() ? st["name"].get<std::string>()
                                                                     : std::to_string(i);
    if (named.contains(name))
      name += "#" + std::to_string(i);
    named[name] = st;
  }
  report["stages"] = named;
  return report;
}

double mean_of(const std::vector<double>& x) {
  double s = 0;
  for (double v : x)
    s += v;
  return s / static_cast<double>(x.size());
}

/// Sample standard deviation (K - 1): [AR]'s "sample-to-sample standard deviation".
json sd_of(const std::vector<double>& x) {
  if (x.size() < 2)
    return nullptr;
  const double m = mean_of(x);
  double s = 0;
  for (double v : x)
    s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(x.size() - 1));
}

/// Statistics of one quantity over the samples' flattened documents (same order as seeds).
json statistics(const std::string& key, const std::vector<std::map<std::string, json>>& docs) {
  std::vector<const json*> present;
  for (const auto& d : docs) {
    auto it = d.find(key);
    present.push_back(it == d.end() ? nullptr : &it->second);
  }
  const json* first =
      *std::find_if(present.begin(), present.end(), [](const json* p) { return p; });
  if (first->is_array()) {
    std::vector<const json*> curves;
    for (const json* p : present)
      if (p)
        curves.push_back(p);
    for (const json* c : curves)
      if (!c->is_array() || c->size() != first->size())
        return nullptr; // lengths differ
    json mean = json::array(), sd = json::array();
    for (std::size_t i = 0; i < first->size(); ++i) {
      std::vector<double> x;
      for (const json* c : curves)
        x.push_back((*c)[i].get<double>());
      mean.push_back(mean_of(x));
      sd.push_back(sd_of(x));
    }
    return {{"mean", mean}, {"sd", sd}, {"K", curves.size()}};
  }
  std::vector<double> x;
  json values = json::array();
  for (const json* p : present) {
    if (p && is_number(*p)) {
      x.push_back(p->get<double>());
      values.push_back(*p);
    } else {
      values.push_back(nullptr);
    }
  }
  if (x.empty())
    return nullptr;
  return {{"mean", mean_of(x)}, {"sd", sd_of(x)}, {"K", x.size()}, {"values", values}};
}

json statistics_of(const std::vector<std::map<std::string, json>>& docs) {
  std::map<std::string, bool> keys;
  for (const auto& d : docs)
    for (const auto& kv : d)
      keys[kv.first] = true;
  json out = json::object();
  for (const auto& kv : keys) {
    json s = statistics(kv.first, docs);
    if (!s.is_null())
      out[kv.first] = s;
  }
  return out;
}

json read_json_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw InputError(path.string() + ": cannot open");
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path.string() + ": not valid JSON: " + e.what());
  }
}

/// The sample directories (sample_<seed>) of an ensemble, by seed.
std::vector<std::pair<std::uint64_t, std::filesystem::path>>
sample_dirs(const std::filesystem::path& out) {
  static const std::regex name(R"(sample_([0-9]{1,18}))");
  std::vector<std::pair<std::uint64_t, std::filesystem::path>> dirs;
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    std::smatch m;
    const std::string base = e.path().filename().string();
    if (e.is_directory() && std::regex_match(base, m, name))
      dirs.emplace_back(std::stoull(m[1].str()), e.path());
  }
  std::sort(dirs.begin(), dirs.end());
  return dirs;
}

/// The configurations of a finished sample worth analysing: the files its write stages made,
/// or final.h5 if there are none (final.h5 then repeats the last written one).
std::vector<std::filesystem::path> configurations(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const auto p = e.path();
    const std::string stem = p.stem().string();
    if (p.extension() == ".h5" && stem != "final" && stem != "checkpoint" && stem != "postmortem")
      files.push_back(p);
  }
  if (files.empty() && std::filesystem::exists(dir / "final.h5"))
    files.push_back(dir / "final.h5");
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<SampleDocuments> read_samples(const std::filesystem::path& out) {
  std::vector<SampleDocuments> samples;
  for (const auto& [seed, dir] : sample_dirs(out)) {
    SampleDocuments s;
    s.seed = seed;
    if (std::filesystem::exists(dir / "report.json")) {
      s.report = read_json_file(dir / "report.json");
      for (const auto& e : std::filesystem::directory_iterator(dir)) {
        const std::string f = e.path().filename().string();
        const std::string suffix = ".analysis.json";
        if (f.size() > suffix.size() &&
            f.compare(f.size() - suffix.size(), suffix.size(), suffix) == 0)
          s.analyses.emplace_back(f.substr(0, f.size() - suffix.size()), read_json_file(e.path()));
      }
      std::sort(s.analyses.begin(), s.analyses.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
    }
    samples.push_back(std::move(s));
  }
  return samples;
}

std::string headline(const json& summary) {
  std::ostringstream os;
  os << "ensemble of " << summary["seeds"].size() << " finished sample(s)";
  if (!summary["unfinished"].empty())
    os << ", " << summary["unfinished"].size() << " unfinished";
  os << "\n";
  if (summary.contains("builds") && summary["builds"].size() > 1) {
    os << "  warning: the samples come from " << summary["builds"].size()
       << " different builds (compare them before pooling):";
    for (const auto& [commit, seeds] : summary["builds"].items())
      os << " " << commit << " (seeds " << seeds.dump() << ")";
    os << "\n";
  }
  for (const auto& [stem, stats] : summary["analysis"].items()) {
    os << "  " << stem << ":";
    for (const char* key : {"/phi", "/z_star", "/x0", "/x2"}) {
      if (!stats.contains(key))
        continue;
      const json& s = stats[key];
      char buf[96];
      if (s["sd"].is_null())
        std::snprintf(buf, sizeof buf, " %s %.5g (K=1)", key + 1, s["mean"].get<double>());
      else
        std::snprintf(buf, sizeof buf, " %s %.5g +- %.2g", key + 1, s["mean"].get<double>(),
                      s["sd"].get<double>());
      os << buf;
    }
    os << "\n";
  }
  return os.str();
}

} // namespace

json summarize_samples(const std::vector<SampleDocuments>& samples) {
  json summary = {{"format", "granpack-ensemble"}, {"format_version", 1}};
  json seeds = json::array(), unfinished = json::array();
  std::vector<std::map<std::string, json>> reports;
  std::map<std::string, std::vector<std::map<std::string, json>>> analyses;
  std::vector<const SampleDocuments*> finished;
  for (const auto& s : samples)
    (s.report.is_null() ? unfinished : seeds).push_back(s.seed);
  for (const auto& s : samples)
    if (!s.report.is_null())
      finished.push_back(&s);
  for (const auto* s : finished)
    for (const auto& a : s->analyses)
      analyses[a.first]; // every stem any sample has
  for (const auto* s : finished) {
    std::map<std::string, json> flat;
    flatten(stages_by_name(s->report), "", flat);
    reports.push_back(std::move(flat));
    for (auto& [stem, docs] : analyses) {
      std::map<std::string, json> a;
      for (const auto& [name, doc] : s->analyses)
        if (name == stem)
          flatten(doc, "", a);
      docs.push_back(std::move(a));
    }
  }
  if (!finished.empty()) {
    const json& r = finished.front()->report;
    if (r.contains("deck"))
      summary["deck"] = r["deck"];
    if (r.contains("n"))
      summary["n"] = r["n"];
    if (r.contains("dimension"))
      summary["dimension"] = r["dimension"];
  }
  summary["seeds"] = seeds;
  summary["K"] = seeds.size();
  // Which code made each sample: samples of one ensemble run by different builds may differ by
  // more than their scatter (a changed protocol), which the statistics alone would hide.
  json builds = json::object();
  for (const auto* s : finished)
    builds[build_of(s->report)].push_back(s->seed);
  summary["builds"] = builds;
  summary["unfinished"] = unfinished;
  summary["report"] = statistics_of(reports);
  summary["analysis"] = json::object();
  for (const auto& [stem, docs] : analyses)
    summary["analysis"][stem] = statistics_of(docs);
  // 2D: the samples' I(k) pooled and fitted once ([GRC] fig. 23 and table VII), beside the
  // statistics of the per-sample fits.
  for (const auto& [stem, docs] : analyses) {
    std::vector<json> density;
    for (const auto* s : finished)
      for (const auto& [name, doc] : s->analyses)
        if (name == stem && doc.contains("density"))
          density.push_back(doc["density"]);
    if (!density.empty())
      summary["density_pooled"][stem] = pooled_density_json(density);
  }
  return summary;
}

std::string summarize_ensemble(MPI_Comm world, const EnsembleSummaryOptions& options) {
  const int rank = rank_of(world);
  const auto& out = options.directory;
  // The files to analyse, listed on rank 0 and broadcast: every rank opens the same ones.
  std::string listing;
  collectively(world, [&] {
    if (rank != 0)
      return;
    if (!std::filesystem::is_directory(out))
      throw InputError(out.string() + ": not a directory (an ensemble's OUT of `run --samples`)");
    const auto dirs = sample_dirs(out);
    if (dirs.empty())
      throw InputError(out.string() +
                       ": holds no sample_<seed> directory (run it with `granpack run "
                       "DECK --samples K -o " +
                       out.string() + "`)");
    json todo = json::array();
    if (options.analyze)
      for (const auto& [seed, dir] : dirs) {
        if (!std::filesystem::exists(dir / "report.json"))
          continue;
        for (const auto& f : configurations(dir)) {
          const auto target = dir / (f.stem().string() + ".analysis.json");
          if (!std::filesystem::exists(target))
            todo.push_back({f.string(), target.string()});
        }
      }
    listing = todo.dump();
  });
  broadcast_string(world, listing);
  for (const auto& item : json::parse(listing)) {
    AnalyzeOptions a;
    a.file = item[0].get<std::string>();
    a.json = item[1].get<std::string>();
    a.print_table = false;
    if (rank == 0)
      std::cout << "analysing " << a.file.string() << " -> " << a.json->string() << std::endl;
    analyze_file(world, a);
  }
  std::string text;
  collectively(world, [&] {
    if (rank != 0)
      return;
    json summary = summarize_samples(read_samples(out));
    summary["directory"] = out.string();
    write_text_atomically(out / "ensemble.json", summary.dump(1) + "\n");
    text = headline(summary) + "wrote " + (out / "ensemble.json").string() + "\n";
  });
  return text;
}

} // namespace granpack
