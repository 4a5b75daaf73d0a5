#pragma once
// `granpack ensemble OUT`: the statistics of an ensemble run (`run --samples`). Reads every
// finished sample's report.json and analysis files (OUT/sample_S/<stem>.analysis.json, written
// by `granpack analyze` or by --analyze here) and writes OUT/ensemble.json: for every number
// the mean, the sample standard deviation (K - 1 in the denominator) and K; curves element-wise.
// Format: docs/report.md, "ensemble.json".
#include <mpi.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace granpack {

struct EnsembleSummaryOptions {
  std::filesystem::path directory;
  /// First analyse the configurations of every finished sample that have no analysis file.
  bool analyze = false;
};

/// One sample's JSON documents: its report and its analyses by configuration stem.
struct SampleDocuments {
  std::uint64_t seed = 0;
  nlohmann::json report; ///< null if not finished
  std::vector<std::pair<std::string, nlohmann::json>> analyses;
};

/// The statistics of the samples (pure: no I/O). Scalars: mean, sd, K, per-seed values;
/// numeric arrays of one length in every sample: element-wise mean and sd.
nlohmann::json summarize_samples(const std::vector<SampleDocuments>& samples);

/// Collective on world (the analyses run on all its ranks). Returns a short text for the
/// terminal; throws InputError if the directory holds no sample.
std::string summarize_ensemble(MPI_Comm world, const EnsembleSummaryOptions& options);

} // namespace granpack
