// `pressure_steps` stage: quasistatic compression (or decompression, factor < 1) by equal
// pressure ratios, P_k = P_0 factor^k (k = 1..count), P_0 the pressure of the previous
// compress stage, each level equilibrated to the [AR] criteria before the next ([AR] table
// III "QS" rows; paper II's sqrt(10) steps). Each level is one compress run with the stage's
// controls and stress ratios of the previous compress; it is recorded as an entry of
// `levels` in report.json and, if `write`, as the file <name>_<k>.h5.
#include <cmath>
#include <sstream>

#include "granpack/engine/checkpoint.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const PressureStepsStage& ps) {
  std::vector<double> stress0 = ctx.stress_target.stress;
  const std::vector<bool> fixed0 = ctx.stress_target.fixed;
  double p0 = ctx.stress_target.pressure;
  StageReport r;
  std::int64_t k = 1;
  // Restart inside this stage: the levels done so far; the level in progress resumes in
  // its compress run (the next frame).
  const nlohmann::json resume = ctx.take_resume_frame();
  if (!resume.is_null()) {
    // The stresses the levels scale: the context now holds those of the last level done.
    k = resume.at("level").get<std::int64_t>();
    p0 = exact_double(resume.at("p0"));
    stress0.clear();
    for (const auto& v : resume.at("stress0"))
      stress0.push_back(exact_double(v));
    for (const auto& l : resume.at("levels"))
      r.levels.push_back(stage_report_from_json(l.dump()));
    for (const auto& l : r.levels)
      r.steps += l.steps, r.time += l.time;
  }
  StageFrame<dim> frame(ctx, [&] {
    nlohmann::json levels = nlohmann::json::array();
    for (const auto& l : r.levels)
      levels.push_back(nlohmann::json::parse(stage_report_json(l)));
    nlohmann::json s0 = nlohmann::json::array();
    for (double v : stress0)
      s0.push_back(exact(v));
    return nlohmann::json{{"stage", "pressure_steps"},
                          {"level", k},
                          {"levels", levels},
                          {"p0", exact(p0)},
                          {"stress0", s0}};
  });
  for (; k <= ps.count; ++k) {
    const double scale = std::pow(ps.factor, static_cast<double>(k));
    CompressStage c = ps.compress;
    c.fixed = fixed0;
    c.stress.clear();
    for (double s : stress0)
      c.stress.push_back(s * scale);
    c.pressure = p0 * scale;
    std::ostringstream os;
    os << "  level " << k << "/" << ps.count << ": P = " << c.pressure << " Pa";
    ctx.log->info(os.str());
    StageReport level = run_stage(ctx, c);
    level.name = ctx.stage_name + "_" + std::to_string(k);
    level.kind = "compress";
    if (ps.write) {
      const std::string file = level.name + ".h5";
      write_state(ctx, ctx.output_dir / file);
      level.values.emplace_back("pressure_target", c.pressure);
      ctx.log->info("  wrote " + (ctx.output_dir / file).string());
    }
    r.steps += level.steps;
    r.time += level.time;
    r.levels.push_back(level);
  }
  // The stage's own entry describes its final level.
  const StageReport& last = r.levels.back();
  r.equilibrated = true;
  for (const auto& l : r.levels)
    r.equilibrated = *r.equilibrated && l.equilibrated.value_or(false);
  r.phi = last.phi;
  r.inertia_max = last.inertia_max;
  r.copy_state_metrics(last);
  return r;
}

template StageReport run_stage<2>(RunContext<2>&, const PressureStepsStage&);
template StageReport run_stage<3>(RunContext<3>&, const PressureStepsStage&);

} // namespace granpack
