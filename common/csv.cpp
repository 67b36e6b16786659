// CSV reading and writing (plain or gzip) with errors that name file, line and column.
#include "csv.hpp"

#include <zlib.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "yaml_config.hpp"

namespace windfdi {

namespace {
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

// gzread handles plain files transparently, so one reader serves both.
struct CsvReader::Source {
  gzFile file = nullptr;
  ~Source() {
    if (file) gzclose(file);
  }
};

CsvReader::CsvReader(const std::string& path) : path_(path), source_(std::make_unique<Source>()) {
  source_->file = gzopen(path.c_str(), "rb");
  if (!source_->file) throw ConfigError(path, 0, "", std::string("cannot open: ") + std::strerror(errno));
  gzbuffer(source_->file, 1 << 16);
  std::string line;
  if (!read_line(line)) throw ConfigError(path, 1, "", "empty file: a header row is required");
  split(line);
  header_ = fields_;
  for (std::size_t i = 0; i < header_.size(); ++i) {
    if (header_[i].empty())
      throw ConfigError(path, 1, "", "empty column name in header at column " + std::to_string(i + 1));
    if (!index_.emplace(header_[i], static_cast<int>(i)).second)
      throw ConfigError(path, 1, header_[i], "column appears twice in the header");
  }
}

CsvReader::~CsvReader() = default;

int CsvReader::column(const std::string& name) const {
  auto it = index_.find(name);
  return it == index_.end() ? -1 : it->second;
}

bool CsvReader::read_line(std::string& line) {
  line.clear();
  char buf[4096];
  while (gzgets(source_->file, buf, sizeof buf)) {
    line.append(buf);
    if (!line.empty() && line.back() == '\n') break;
  }
  int err = 0;
  const char* msg = gzerror(source_->file, &err);
  if (err != Z_OK && err != Z_STREAM_END)
    throw ConfigError(path_, line_ + 1, "", std::string("read error: ") + msg);
  if (line.empty()) return false;
  ++line_;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return true;
}

void CsvReader::split(const std::string& line) {
  fields_.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string f = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    // Trim surrounding blanks: hand-edited files often have them.
    const auto b = f.find_first_not_of(" \t");
    const auto e = f.find_last_not_of(" \t");
    fields_.push_back(b == std::string::npos ? std::string() : f.substr(b, e - b + 1));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
}

bool CsvReader::next() {
  std::string line;
  while (read_line(line)) {
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    split(line);
    if (fields_.size() != header_.size())
      throw ConfigError(path_, line_, "",
                        "row has " + std::to_string(fields_.size()) + " fields, header has " +
                            std::to_string(header_.size()));
    return true;
  }
  return false;
}

double CsvReader::number(int col) const {
  const std::string& f = fields_.at(static_cast<std::size_t>(col));
  if (f.empty()) return std::nan("");
  const char* begin = f.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0')
    throw ConfigError(path_, line_, header_.at(static_cast<std::size_t>(col)),
                      "'" + f + "' is not a number (column " + std::to_string(col + 1) + ")");
  return v;
}

struct CsvWriter::Sink {
  gzFile gz = nullptr;
  std::FILE* plain = nullptr;
  ~Sink() {
    if (gz) gzclose(gz);
    if (plain) std::fclose(plain);
  }
};

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& header)
    : path_(path), sink_(std::make_unique<Sink>()), columns_(header.size()) {
  if (ends_with(path, ".gz")) {
    // Level 1: recordings are large and the simulator is faster than zlib at its default level.
    sink_->gz = gzopen(path.c_str(), "wb1");
  } else {
    sink_->plain = std::fopen(path.c_str(), "wb");
  }
  if (!sink_->gz && !sink_->plain)
    throw ConfigError(path, 0, "", std::string("cannot create: ") + std::strerror(errno));
  std::string line;
  for (std::size_t i = 0; i < header.size(); ++i) line += (i ? "," : "") + header[i];
  line += '\n';
  write(line.data(), line.size());
}

CsvWriter::~CsvWriter() = default;

CsvWriter& CsvWriter::add(double value) { return add(format_number(value)); }

CsvWriter& CsvWriter::add(const std::string& text) {
  if (fields_in_row_++) row_ += ',';
  row_ += text;
  return *this;
}

void CsvWriter::end_row() {
  if (fields_in_row_ != columns_)
    throw std::logic_error(path_ + ": row with " + std::to_string(fields_in_row_) + " fields, header has " +
                           std::to_string(columns_));
  row_ += '\n';
  write(row_.data(), row_.size());
  row_.clear();
  fields_in_row_ = 0;
}

void CsvWriter::flush() {
  if (sink_->gz) gzflush(sink_->gz, Z_SYNC_FLUSH);
  if (sink_->plain) std::fflush(sink_->plain);
}

void CsvWriter::write(const char* data, std::size_t size) {
  const bool ok = sink_->gz ? gzwrite(sink_->gz, data, static_cast<unsigned>(size)) == static_cast<int>(size)
                            : std::fwrite(data, 1, size, sink_->plain) == size;
  if (!ok) throw std::runtime_error(path_ + ": write failed");
}

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, res.ptr);
}

}  // namespace windfdi
