#pragma once
// The human log: rank 0 writes to the terminal and to DIR/log.txt; other ranks stay silent.
// Levels: info (always), progress (in quiet mode to the log file only: a batch job's terminal
// output stays short while DIR/log.txt still shows how far a long stage has come), warn
// (always). Every line is flushed so that a killed job leaves a complete log.
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

namespace granpack {

class Log {
public:
  /// `is_root`: whether this rank writes; `quiet`: progress lines to the file only.
  Log(bool is_root, bool quiet) : root_(is_root), quiet_(quiet) {}
  /// Also append every line to this file (rank 0 only; created, or truncated unless
  /// `append`: a restarted run continues the interrupted run's log).
  void open_file(const std::string& path, bool append = false);
  void info(const std::string& line) { emit(line, false); }
  void progress(const std::string& line) {
    if (quiet_)
      emit_to_file(line);
    else
      emit(line, false);
  }
  void warn(const std::string& line) { emit("warning: " + line, true); }
  /// To log.txt only: why a run ended (the terminal gets the same message from main), so
  /// that the log of a batch job says whether it finished, was stopped or failed.
  void record(const std::string& line) { emit_to_file(line); }
  bool quiet() const { return quiet_; }
  /// Put before every terminal line (not the file's): which sample of an ensemble speaks.
  void set_terminal_prefix(std::string prefix) { prefix_ = std::move(prefix); }

private:
  void emit(const std::string& line, bool to_stderr);
  void emit_to_file(const std::string& line);
  bool root_, quiet_;
  std::string prefix_;
  std::unique_ptr<std::ofstream> file_;
};

} // namespace granpack
