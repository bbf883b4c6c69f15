// CSV training log (training/log.h).
#include "simpli/model/training/log.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace simpli::training {
namespace {

std::string joinHeader(const std::vector<std::string>& columns) {
  std::string s;
  for (size_t i = 0; i < columns.size(); ++i)
    s += (i ? "," : "") + columns[i];
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ','))
    out.push_back(cell);
  if (!line.empty() && line.back() == ',')
    out.emplace_back();
  return out;
}

double parseCell(const std::string& cell, const std::string& path, size_t row) {
  if (cell.empty() || cell == "nan")
    return std::nan("");
  try {
    size_t used = 0;
    const double v = std::stod(cell, &used);
    if (used != cell.size())
      throw std::invalid_argument(cell);
    return v;
  } catch (const std::exception&) {
    fail(path, ": row ", row, ": value '", cell, "' is not a number");
  }
}

} // namespace

std::vector<std::vector<double>> TrainLog::read(const std::string& path,
                                                std::vector<std::string>* header) {
  std::ifstream in(path);
  if (!in)
    fail(path, ": cannot open the training log");
  std::string line;
  if (!std::getline(in, line))
    fail(path, ": the training log is empty (no header)");
  const std::vector<std::string> cols = split(line);
  if (header)
    *header = cols;
  std::vector<std::vector<double>> rows;
  size_t row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty())
      continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() != cols.size())
      fail(path, ": row ", row, " has ", cells.size(), " values; the header has ", cols.size());
    std::vector<double> values;
    for (const std::string& c : cells)
      values.push_back(parseCell(c, path, row));
    rows.push_back(std::move(values));
  }
  return rows;
}

TrainLog::TrainLog(const std::string& path, std::vector<std::string> columns, long long resumeStep)
    : path_(path), columns_(std::move(columns)) {
  const std::string header = joinHeader(columns_);
  std::string kept = header + "\n";
  if (resumeStep >= 0 && std::filesystem::exists(path)) {
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line) || line != header)
      fail(path, ": header '", line, "' differs from this run's columns '", header,
           "'; cannot resume this log");
    // Keep whole, well-formed rows up to the resumed step; a torn last line (a crash in the
    // middle of a write) is dropped with the rest.
    while (std::getline(in, line)) {
      const std::vector<std::string> cells = split(line);
      if (cells.size() != columns_.size() || cells[0].empty())
        break;
      char* end = nullptr;
      const long long step = std::strtoll(cells[0].c_str(), &end, 10);
      if (*end != '\0' || step > resumeStep)
        break;
      kept += line + "\n";
    }
  }
  io::writeFileAtomically(path, kept.data(), kept.size());
  file_ = std::fopen(path.c_str(), "a");
  if (!file_)
    fail(path, ": cannot open the training log for appending: ", std::strerror(errno));
}

TrainLog::~TrainLog() {
  if (file_)
    std::fclose(file_);
}

void TrainLog::append(const std::vector<double>& values) {
  if (values.size() != columns_.size())
    fail(path_, ": a row of ", values.size(), " values for ", columns_.size(), " columns");
  std::string line;
  char buf[64];
  for (size_t i = 0; i < values.size(); ++i) {
    if (i == 0)
      std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(values[0]));
    else if (std::isnan(values[i]))
      std::snprintf(buf, sizeof buf, "nan");
    else
      std::snprintf(buf, sizeof buf, "%.17g", values[i]);
    line += (i ? "," : "") + std::string(buf);
  }
  line += "\n";
  if (std::fputs(line.c_str(), file_) < 0 || std::fflush(file_) != 0)
    fail(path_, ": cannot write the training log: ", std::strerror(errno));
}

} // namespace simpli::training
