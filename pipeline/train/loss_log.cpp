#include "pipeline/train/loss_log.h"

#include <fstream>
#include <sstream>

#include "nets/io/file_io.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

std::string joined(const std::vector<std::string>& columns) {
  std::string line;
  for (const std::string& c : columns) {
    if (!line.empty()) line += ',';
    line += c;
  }
  return line;
}

std::string formatted(double value) {
  std::ostringstream text;
  text.precision(9);
  text << value;
  return text.str();
}

std::string joinedValues(const std::vector<double>& values) {
  std::string line;
  for (const double v : values) {
    if (!line.empty()) line += ',';
    line += formatted(v);
  }
  return line;
}

}  // namespace

CsvLog::CsvLog(std::filesystem::path path, std::vector<std::string> columns, int64_t keepUpTo)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty() || columns_[0] != "step") throw Error("csv log: the first column must be 'step'");
  std::ifstream file(path_);
  if (file && keepUpTo >= 0) {
    std::string header;
    std::getline(file, header);
    if (!header.empty() && header != joined(columns_))
      throw Error(path_.string() + ": its columns (" + header + ") are not this run's (" + joined(columns_) +
                  "); it belongs to another run (use --overwrite to start afresh)");
    for (std::string line; std::getline(file, line);) {
      if (line.empty()) continue;
      std::vector<double> row;
      std::stringstream fields(line);
      for (std::string field; std::getline(fields, field, ',');) row.push_back(std::stod(field));
      if (row.size() != columns_.size()) throw Error(path_.string() + ": a row with " + std::to_string(row.size()) +
                                                     " values, expected " + std::to_string(columns_.size()));
      if (row[0] <= static_cast<double>(keepUpTo)) rows_.push_back(row);
    }
  }
  rewrite();
}

void CsvLog::append(const std::vector<double>& values) {
  if (values.size() != columns_.size())
    throw Error(path_.string() + ": " + std::to_string(values.size()) + " values for " +
                std::to_string(columns_.size()) + " columns");
  rows_.push_back(values);
  std::ofstream file(path_, std::ios::app);
  file << joinedValues(values) << "\n";
  if (!file) throw Error(path_.string() + ": cannot append to the log");
}

void CsvLog::rewrite() const {
  io::writeAtomically(path_, [&](const std::filesystem::path& temporary) {
    std::ofstream file(temporary);
    file << joined(columns_) << "\n";
    for (const auto& row : rows_) {
      file << joinedValues(row) << "\n";
    }
    if (!file) throw Error(temporary.string() + ": cannot write the log");
  });
}

}  // namespace smokesvd::train
