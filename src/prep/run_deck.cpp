#include "granpack/prep/run_deck.h"

#include <chrono>
#include <sstream>

#include "granpack/comm/collective_error.h"
#include "granpack/core/error.h"
#include "granpack/io/deck.h"
#include "granpack/prep/stages.h"

namespace granpack {

namespace {

/// Reads the deck on rank 0 and broadcasts its text, so all ranks validate the same bytes
/// and throw the same InputError together.
Deck load_deck_collectively(MPI_Comm world, const std::filesystem::path& path) {
  int rank = 0;
  MPI_Comm_rank(world, &rank);
  std::string text;
  int ok = 1;
  if (rank == 0) {
    try {
      text = read_deck_text(path);
    } catch (const InputError& e) {
      text = e.what();
      ok = 0;
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, world);
  long long len = static_cast<long long>(text.size());
  MPI_Bcast(&len, 1, MPI_LONG_LONG, 0, world);
  text.resize(static_cast<std::size_t>(len));
  MPI_Bcast(text.data(), static_cast<int>(len), MPI_CHAR, 0, world);
  if (!ok) throw InputError(text);  // on every rank, same message
  return parse_deck(text, path.string());
}

std::string fmt_opt(const std::optional<double>& v) {
  if (!v) return "-";
  std::ostringstream os;
  os.precision(6);
  os << *v;
  return os.str();
}

template <int dim> void run_stages(MPI_Comm world, const Deck& deck, Log& log,
                                   const std::filesystem::path& out, RunReport& report) {
  RunContext<dim> ctx;
  ctx.world = world;
  ctx.deck = &deck;
  ctx.material = deck.material;
  ctx.log = &log;
  ctx.output_dir = out;
  for (const auto& st : deck.stages) {
    ctx.stage_index = st.index;
    ctx.stage_name = st.name;
    log.info("stage " + std::to_string(st.index) + " '" + st.name + "' (" + st.kind + ")");
    auto t0 = std::chrono::steady_clock::now();
    StageReport r = std::visit(
        [&](const auto& p) -> StageReport {
          using P = std::decay_t<decltype(p)>;
          if constexpr (std::is_same_v<P, LatticeStage>) return run_lattice(ctx, p);
          else if constexpr (std::is_same_v<P, RandomStage>) return run_random(ctx, p);
          else if constexpr (std::is_same_v<P, CompressStage>) return run_compress(ctx, p);
          else if constexpr (std::is_same_v<P, SetStage>) return run_set(ctx, p);
          else if constexpr (std::is_same_v<P, WriteStage>) return run_write(ctx, p);
          else if constexpr (std::is_same_v<P, ReadStage>) return run_read(ctx, p);
          else if constexpr (std::is_same_v<P, EdGasStage>) return run_ed_gas(ctx, p);
          else if constexpr (std::is_same_v<P, LsCompressStage>) return run_ls_compress(ctx, p);
          else if constexpr (std::is_same_v<P, ExpandStage>) return run_expand(ctx, p);
          else if constexpr (std::is_same_v<P, PressureStepsStage>) return run_pressure_steps(ctx, p);
          else if constexpr (std::is_same_v<P, FixRattlersStage>) return run_fix_rattlers(ctx, p);
          else throw NotImplemented("stage kind '" + st.kind + "' is not implemented yet");
        },
        st.params);
    r.name = st.name;
    r.kind = st.kind;
    if (!r.phi && ctx.decomposition) r.phi = ctx.solid_fraction();
    // set and write leave the packing as it was: its network metrics carry over.
    if ((st.kind == "set" || st.kind == "write") && !report.stages.empty())
      r.copy_state_metrics(report.stages.back());
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    report.stages.push_back(r);
    log.info("  done: phi " + fmt_opt(r.phi) + ", steps " + std::to_string(r.steps) +
             ", wall " + fmt_opt(r.wall_seconds) + " s");
  }
  GRANPACK_CHECK(ctx.decomposition, "the deck never builds a sample (no lattice/random stage)");
  write_state(ctx, out / "final.h5");
  report.final_file = "final.h5";
  log.info("wrote " + (out / "final.h5").string());
}

}  // namespace

int run_deck(MPI_Comm world, const RunOptions& options) {
  auto t0 = std::chrono::steady_clock::now();
  int rank = 0, size = 1;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &size);

  // 1. Validate everything before touching the output directory.
  Deck deck = load_deck_collectively(world, options.deck);
  if (options.restart)
    throw NotImplemented("--restart is not implemented yet (checkpoint/restart: issue 7)");
  for (const auto& st : deck.stages)
    if (!stage_implemented(st.kind))
      throw NotImplemented(deck.file + ": stage[" + std::to_string(st.index) + "] kind = \"" +
                           st.kind + "\" is part of the deck language but not implemented in "
                           "granpack " GRANPACK_VERSION "; nothing was run or written");

  std::filesystem::path out = options.output_dir;
  if (out.empty()) out = std::filesystem::path("out") / options.deck.stem();
  collectively(world, [&] {
    if (rank == 0) {
      std::error_code ec;
      std::filesystem::create_directories(out, ec);
      if (ec) throw InputError("cannot create the output directory " + out.string() + ": " + ec.message());
    }
  });

  Log log(rank == 0, options.quiet || deck.output.quiet);
  collectively(world, [&] { log.open_file((out / "log.txt").string()); });
  log.info("granpack " GRANPACK_VERSION ": " + deck.file + " -> " + out.string() + " on " +
           std::to_string(size) + " rank(s), dimension " + std::to_string(deck.sample.dimension) +
           ", n = " + std::to_string(deck.sample.n));

  RunReport report;
  report.version = GRANPACK_VERSION;
  report.dimension = deck.sample.dimension;
  report.n = deck.sample.n;
  report.ranks = size;
  report.deck = options.deck.string();
  if (deck.sample.dimension == 3)
    run_stages<3>(world, deck, log, out, report);
  else
    run_stages<2>(world, deck, log, out, report);

  report.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  collectively(world, [&] {
    if (rank == 0) write_report(out / "report.json", report);
  });
  log.info("wrote " + (out / "report.json").string());
  return kExitOk;
}

}  // namespace granpack
