// granpack: the command-line entry point. A thin main: parse the command line with CLI11,
// initialise MPI, call the library, map exceptions to exit codes (docs/cli.md).
#include <mpi.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <iostream>

#include "granpack/app/analyze.h"
#ifdef GRANPACK_HAVE_RIGIDITY
#include "granpack/app/stiffness.h"
#include "granpack/rigidity/petsc_support.h"
#endif
#include "granpack/app/bench.h"
#include "granpack/app/build_info.h"
#include "granpack/app/ensemble_run.h"
#include "granpack/app/ensemble_summary.h"
#include "granpack/app/run_deck.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/fault_injection.h"
#include "granpack/core/error.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/mpiio_hints.h"

using granpack::rank_of;

int main(int argc, char** argv) {
  // A file size limit (ulimit -f) must not kill a rank with SIGXFSZ, silently and alone: with
  // the signal ignored, write() fails with EFBIG and the collective write-failure path runs
  // (every rank stops with the message, exit code 74; docs/long-jobs.md).
  std::signal(SIGXFSZ, SIG_IGN);
  MPI_Init(&argc, &argv);
  const bool root = rank_of(MPI_COMM_WORLD) == 0;

  CLI::App app{"granpack " GRANPACK_VERSION
               ": model granular packings - assembly, equilibration, analysis, rigidity.\n"
               "Run under MPI, e.g.  mpirun -np 2 granpack run DECK.toml -o out/A",
               "granpack"};
  app.set_version_flag("--version", granpack::build_description());
  app.require_subcommand(1);

  granpack::RunOptions run;
  std::string restart;
  auto* run_cmd = app.add_subcommand("run", "assemble/equilibrate a packing as a deck says");
  run_cmd->add_option("deck", run.deck, "TOML deck (docs/deck.md)")->required();
  run_cmd->add_option("-o,--output", run.output_dir, "output directory (default out/<deck stem>)");
  run_cmd
      ->add_option("--restart", restart,
                   "continue from this checkpoint file (DIR/checkpoint.h5); with --samples, no "
                   "file: resume the unfinished samples, skip the finished ones")
      ->expected(0, 1);
  std::uint64_t seed = 0;
  run_cmd
      ->add_option("--seed", seed, "run the deck with this [sample] seed (docs/deck.md, \"Seeds\")")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{9223372036854775807ULL}));
  int samples = 0, ranks_per_sample = 0;
  std::uint64_t first_seed = 1;
  run_cmd
      ->add_option(
          "--samples", samples,
          "an ensemble: run K samples (seeds S..S+K-1) side by side, each in OUT/sample_<seed>/")
      ->check(CLI::Range(1, 1000000));
  run_cmd
      ->add_option("--first-seed", first_seed,
                   "with --samples: the first sample's seed (default 1)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{9223372036854775807ULL}));
  run_cmd
      ->add_option("--ranks-per-sample", ranks_per_sample,
                   "with --samples: MPI ranks of each sample (default: the ranks shared evenly, "
                   "else 1); must divide the job's ranks")
      ->check(CLI::Range(1, 1000000));
  run_cmd->add_flag(
      "--allow-deck-change", run.allow_deck_change,
      "on --restart, let the stages after the one in progress differ from the checkpoint's deck");
  std::int64_t ckpt_steps = -1;
  double ckpt_seconds = -1;
  run_cmd
      ->add_option("--checkpoint-every-steps", ckpt_steps,
                   "steps between checkpoints, 0: off (overrides the deck)")
      ->check(CLI::NonNegativeNumber);
  run_cmd
      ->add_option("--checkpoint-every-seconds", ckpt_seconds,
                   "wall seconds between checkpoints, 0: off (overrides the deck)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_flag("-q,--quiet", run.quiet,
                    "no progress lines on the terminal (batch mode); log.txt keeps them");

  std::string file, json_out;
  auto* analyze_cmd =
      app.add_subcommand("analyze", "geometric and mechanical analysis of a packing");
  analyze_cmd->add_option("file", file, "configuration file (.h5)")->required();
  analyze_cmd->add_option("--json", json_out, "also write the results as JSON to this file");
  std::string h5_out;
  analyze_cmd->add_option("--h5", h5_out,
                          "also write the results as HDF5 (curves, histograms as datasets)");
  double analyze_threshold = granpack::AnalyzeOptions{}.threshold;
  analyze_cmd
      ->add_option("--threshold", analyze_threshold,
                   "force-carrying threshold / (a^2 P), a^(dim-1) P in 2D (default 1e-4, [AR]'s "
                   "tolerance); raising it shows how much of x0, z*, x2 sits in weak contacts")
      ->check(CLI::Validator(
          [](const std::string& text) {
            // CLI11's PositiveNumber & Range print the type's limits; say what is allowed.
            double t = 0;
            if (!CLI::detail::lexical_cast(text, t) || !(t > 0 && t <= 1))
              return "a fraction in (0, 1] expected, got " + text;
            return std::string();
          },
          "in (0, 1]"));
  granpack::PairOptions pair_opts;
  analyze_cmd->add_option("--gr-max", pair_opts.r_max, "range of g(r) in diameters (default 3)")
      ->check(CLI::Range(1.5, 100.0));
  analyze_cmd
      ->add_option("--gr-bin", pair_opts.bin_width, "bin width of g(r) in diameters (default 0.01)")
      ->check(CLI::Range(1e-4, 1.0));
  granpack::DensityOptions density_opts;
  bool no_density = false;
  analyze_cmd->add_flag("--no-density", no_density, "2D: skip I(k), the fractal fit and the holes");
  analyze_cmd
      ->add_option("--mesh", density_opts.spacing,
                   "2D: mesh spacing of the density field in diameters (default 0.01)")
      ->check(CLI::Range(1e-4, 0.5));
  analyze_cmd
      ->add_option("--fit-kmax", density_opts.k_max_wavelength,
                   "2D: fit eq. (28) up to k = 2 pi / (this * a) (default 1)")
      ->check(CLI::Range(0.05, 100.0));
  analyze_cmd
      ->add_option("--fit-rmin", density_opts.r_min,
                   "2D: fit eq. (27) to C(r) from r = this * a (default 1)")
      ->check(CLI::Range(0.0, 100.0));
  auto* stiffness_cmd = app.add_subcommand("stiffness", "rigidity, mechanisms and elastic moduli");
  stiffness_cmd->add_option("file", file, "configuration file (.h5)")->required();
  stiffness_cmd->add_option("--json", json_out, "also write the results as JSON to this file");
  double stiffness_threshold = 1e-4, null_pivot_threshold = 1e-12;
  int stiffness_eigenvalues = 6;
  stiffness_cmd
      ->add_option("--threshold", stiffness_threshold,
                   "force-carrying threshold / (a^2 P) (default 1e-4, as analyze)")
      ->check(CLI::Range(0.0, 1.0));
  stiffness_cmd
      ->add_option("--null-pivot", null_pivot_threshold,
                   "MUMPS null-pivot threshold relative to |K| (default 1e-12)")
      ->check(CLI::Range(1e-300, 1e-2));
  stiffness_cmd
      ->add_option("--eigenvalues", stiffness_eigenvalues,
                   "smallest eigenvalues of the stiffened K(1) to report (default 6)")
      ->check(CLI::Range(1, 1000));
  int stiffness_modes = 0;
  std::string modes_file;
  stiffness_cmd
      ->add_option("--modes", stiffness_modes,
                   "write the K softest modes of the stiffened K(1) as displacement fields "
                   "(needs --modes-file)")
      ->check(CLI::Range(1, 1000));
  stiffness_cmd->add_option("--modes-file", modes_file,
                            "HDF5 file for --modes (an XDMF sidecar is written beside it)");
  std::string stiffness_solver = "auto";
  stiffness_cmd
      ->add_option("--solver", stiffness_solver,
                   "moduli by a factorisation (direct: also counts the mechanisms), by Krylov "
                   "solves with multigrid (krylov: the moduli only), or auto (krylov above "
                   "--krylov-above grain unknowns; default)")
      ->check(CLI::IsMember({"direct", "krylov", "auto"}));
  std::int64_t krylov_above = 300000;
  stiffness_cmd
      ->add_option("--krylov-above", krylov_above,
                   "auto: Krylov path above this many grain unknowns (default 300000)")
      ->check(CLI::Range(std::int64_t(0), std::int64_t(1) << 62));
  double krylov_rtol = 1e-8;
  stiffness_cmd
      ->add_option("--krylov-rtol", krylov_rtol,
                   "relative residual of each Krylov solve (default 1e-8)")
      ->check(CLI::Range(1e-15, 1e-2));
  granpack::BenchOptions bench;
  std::string bench_data, bench_forces, bench_json;
  auto* bench_cmd =
      app.add_subcommand("bench", "time the MD engine on a dense packing (docs/performance.md)");
  bench_cmd->add_option("file", bench.file, "3D packing (.h5), e.g. docs/data/A_n4000_seed1.h5")
      ->required();
  bench_cmd->add_option("--replicate", bench.replicate, "periodic copies per axis, e.g. 2 2 2");
  bench_cmd->add_option("--steps", bench.steps, "timed steps (default 1000)")
      ->check(CLI::PositiveNumber);
  bench_cmd->add_option("--velocity", bench.velocity_rms,
                        "initial rms velocity per axis, m/s (default 1e-3)");
  bench_cmd->add_option("--lammps-data", bench_data,
                        "also write the initial state as a LAMMPS data file");
  bench_cmd->add_option("--static-forces", bench_forces,
                        "also write the static force on each grain");
  bench_cmd->add_option("--json", bench_json, "also write the results as JSON to this file");
  bench_cmd
      ->add_option("--halo", bench.halo,
                   "the halo's transport, as [numerics] halo (default shared_memory)")
      ->check(CLI::IsMember({"messages", "shared_memory"}));
  std::vector<std::string> check_paths;
  auto* check_cmd =
      app.add_subcommand("check", "validate decks as `run` would, without running them");
  check_cmd->add_option("decks", check_paths, "TOML decks (docs/deck.md)")->required();

  granpack::EnsembleSummaryOptions ensemble;
  auto* ensemble_cmd =
      app.add_subcommand("ensemble", "mean, standard deviation and K of every number of an "
                                     "ensemble's samples -> OUT/ensemble.json");
  ensemble_cmd->add_option("directory", ensemble.directory, "the OUT of `run --samples K -o OUT`")
      ->required();
  ensemble_cmd->add_flag(
      "--analyze", ensemble.analyze,
      "first run `analyze` on every finished sample's configurations that have no "
      "<stem>.analysis.json yet");

  auto* info_cmd = app.add_subcommand("info", "what a granpack HDF5 file holds");
  info_cmd->add_option("file", file, "granpack HDF5 file")->required();

  int code = granpack::kExitOk;
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      int c = root ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 1);
      code = c == 0 ? granpack::kExitOk : granpack::kExitBadInput;
      MPI_Finalize();
      return code;
    }
    granpack::arm_fault_injection(MPI_COMM_WORLD); // test-only, GRANPACK_FAULT (docs/long-jobs.md)
    granpack::check_mpiio_hints(); // GRANPACK_MPIIO_HINTS: a typo stops the job now, not at a
                                   // checkpoint
    if (*run_cmd) {
      const bool restarting = run_cmd->count("--restart") > 0;
      if (ckpt_steps >= 0)
        run.checkpoint_every_steps = ckpt_steps;
      if (ckpt_seconds >= 0)
        run.checkpoint_every_seconds = ckpt_seconds;
      if (samples > 0) {
        if (run_cmd->count("--seed"))
          throw granpack::InputError(
              "--seed and --samples exclude each other: sample S of an ensemble has seed S "
              "(--first-seed sets the first)");
        if (!restart.empty())
          throw granpack::InputError("--restart " + restart +
                                     ": with --samples, --restart takes no file; each "
                                     "sample resumes from its own OUT/sample_<seed>/checkpoint.h5");
        granpack::EnsembleOptions e;
        e.run = run;
        e.samples = samples;
        e.first_seed = first_seed;
        e.ranks_per_sample = ranks_per_sample;
        e.resume = restarting;
        code = granpack::run_ensemble(MPI_COMM_WORLD, e);
      } else {
        if (run_cmd->count("--first-seed") || run_cmd->count("--ranks-per-sample"))
          throw granpack::InputError(
              "--first-seed and --ranks-per-sample apply to an ensemble: add --samples K");
        if (restarting && restart.empty())
          throw granpack::InputError(
              "--restart needs the checkpoint file, e.g. --restart out/A/checkpoint.h5");
        if (!restart.empty())
          run.restart = restart;
        if (run_cmd->count("--seed"))
          run.seed = seed;
        code = granpack::run_deck(MPI_COMM_WORLD, run);
      }
    } else if (*ensemble_cmd) {
      std::string text = granpack::summarize_ensemble(MPI_COMM_WORLD, ensemble);
      if (root)
        std::cout << text;
    } else if (*bench_cmd) {
      if (!bench_data.empty())
        bench.lammps_data = bench_data;
      if (!bench_forces.empty())
        bench.static_forces = bench_forces;
      if (!bench_json.empty())
        bench.json = bench_json;
      std::string text = granpack::run_bench(MPI_COMM_WORLD, bench);
      if (root)
        std::cout << text;
    } else if (*check_cmd) {
      std::string text =
          granpack::check_decks(MPI_COMM_WORLD, {check_paths.begin(), check_paths.end()});
      if (root)
        std::cout << text;
    } else if (*info_cmd) {
      std::string text = granpack::describe_file(MPI_COMM_WORLD, file);
      if (root)
        std::cout << text;
    } else if (*analyze_cmd) {
      granpack::AnalyzeOptions a;
      a.file = file;
      a.threshold = analyze_threshold;
      a.pairs = pair_opts;
      a.density = density_opts;
      a.density.enabled = !no_density;
      if (!json_out.empty())
        a.json = json_out;
      if (!h5_out.empty())
        a.hdf5 = h5_out;
      granpack::analyze_file(MPI_COMM_WORLD, a);
    } else if (*stiffness_cmd) {
#ifdef GRANPACK_HAVE_RIGIDITY
      granpack::StiffnessOptions s;
      s.file = file;
      s.threshold = stiffness_threshold;
      s.null_pivot_threshold = null_pivot_threshold;
      s.eigenvalues = stiffness_eigenvalues;
      if ((stiffness_modes > 0) != !modes_file.empty())
        throw granpack::InputError("stiffness: --modes and --modes-file go together");
      s.modes = stiffness_modes;
      s.solver = stiffness_solver == "direct"   ? granpack::StiffnessSolver::kDirect
                 : stiffness_solver == "krylov" ? granpack::StiffnessSolver::kKrylov
                                                : granpack::StiffnessSolver::kAuto;
      s.krylov_above = krylov_above;
      s.krylov_rtol = krylov_rtol;
      if (!modes_file.empty())
        s.modes_file = modes_file;
      if (!json_out.empty())
        s.json = json_out;
      granpack::stiffness_file(MPI_COMM_WORLD, s);
#else
      throw granpack::NotImplemented("this granpack was built without GRANPACK_ENABLE_RIGIDITY");
#endif
    }
  } catch (const granpack::CheckpointedStop& e) {
    // Not an error: the batch system asked us to stop and the state is saved.
    if (root)
      std::cerr << "granpack: " << e.what() << std::endl;
    code = e.exit_code();
  } catch (const granpack::Error& e) {
    // granpack errors are collective by construction (docs/ARCHITECTURE.md, "Errors"): every
    // rank arrives here with the same message, rank 0 says it once.
    if (root)
      std::cerr << "granpack: error: " << e.what() << std::endl;
    code = e.exit_code();
  } catch (const std::exception& e) {
    // Not known to be collective: the other ranks may be waiting in a collective call.
    std::cerr << "granpack: fatal error on rank " << rank_of(MPI_COMM_WORLD) << ": " << e.what()
              << std::endl;
    MPI_Abort(MPI_COMM_WORLD, granpack::kExitFailure);
  }
  if (granpack::hdf5_file_left_open()) {
    // After a failed parallel write, HDF5 1.10.8 segfaults in its shutdown at MPI_Finalize
    // (H5F__close_cb, on every rank that took part): skip the shutdown. Every rank is here
    // (write failures are collective); the barrier lets rank 0's message out first, since
    // mpirun stops the job when any rank ends with a non-zero code.
    MPI_Barrier(MPI_COMM_WORLD);
    std::cout.flush();
    std::cerr.flush();
    std::_Exit(code);
  }
#ifdef GRANPACK_HAVE_RIGIDITY
  granpack::finalize_petsc();
#endif
  MPI_Finalize();
  return code;
}
