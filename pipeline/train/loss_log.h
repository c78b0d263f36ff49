// The CSV logs of a training run: loss.csv (step, seconds, learning rate, total, each term) and
// validation.csv (step, each metric). Rows are appended as the run goes; when a run resumes from a
// checkpoint taken at step s, rows after s are dropped first, so the files equal an uninterrupted run's.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace smokesvd::train {

class CsvLog {
 public:
  // Opens `path` with `columns` (the first must be "step"); keeps only rows with step <= keepUpTo
  // (all when the file is new or keepUpTo < 0 drops every row). A header that differs is an Error.
  CsvLog(std::filesystem::path path, std::vector<std::string> columns, int64_t keepUpTo);
  void append(const std::vector<double>& values);  // one value per column, step first
  // Every row so far (for the plot).
  const std::vector<std::vector<double>>& rows() const { return rows_; }
  const std::vector<std::string>& columns() const { return columns_; }

 private:
  void rewrite() const;
  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> rows_;
};

}  // namespace smokesvd::train
