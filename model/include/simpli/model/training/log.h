#pragma once
// The per-step training log: a CSV file (header "step,<loss terms...>,total,lr,grad_norm,
// step_ms"), one row appended and flushed per step. Values are printed with 17 significant
// digits so that they read back exactly. On resume the file is cut back to the rows with step
// <= the resumed step (rows written after the checkpoint belong to steps that are redone).
#include <cstdio>
#include <string>
#include <vector>

namespace simpli::training {

class TrainLog {
public:
  /// Opens `path`. resumeStep < 0: a new log (an existing file is replaced). resumeStep >= 0:
  /// the existing file is kept up to that step (its header must equal `columns`; a missing
  /// file starts a new log). Throws simpli::Error naming the file.
  TrainLog(const std::string& path, std::vector<std::string> columns, long long resumeStep);
  ~TrainLog();
  TrainLog(const TrainLog&) = delete;
  TrainLog& operator=(const TrainLog&) = delete;

  /// One row; values.size() must equal the number of columns; the first is the step.
  void append(const std::vector<double>& values);
  const std::string& path() const { return path_; }

  /// The rows of a log file (header checked against `columns` when not empty); for tests and
  /// tools.
  static std::vector<std::vector<double>> read(const std::string& path,
                                               std::vector<std::string>* header = nullptr);

private:
  std::string path_;
  std::vector<std::string> columns_;
  std::FILE* file_ = nullptr;
};

} // namespace simpli::training
