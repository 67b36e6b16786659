// CSV reading and writing (plain or gzip) with errors that name file, line and column.
#pragma once

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace windfdi {

/// Reads a CSV file with a header row; a `.gz` file (or gzip content) is decompressed on the fly.
/// Columns are addressed by name; malformed rows throw ConfigError(file, line, column).
class CsvReader {
 public:
  explicit CsvReader(const std::string& path);
  ~CsvReader();
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  /// Index of a column, or -1 when the file has no such column.
  int column(const std::string& name) const;
  /// Reads the next data row; false at the end of the file. Blank lines are skipped.
  bool next();
  /// Line number (1-based) of the current row.
  long line() const { return line_; }
  /// The field as text.
  const std::string& text(int col) const { return fields_.at(static_cast<std::size_t>(col)); }
  /// The field as a number. Empty, "nan" and "inf" are accepted (they are samples the services reject);
  /// anything that is not a number is a malformed file.
  double number(int col) const;

 private:
  bool read_line(std::string& line);
  void split(const std::string& line);

  std::string path_;
  struct Source;
  std::unique_ptr<Source> source_;
  std::vector<std::string> header_;
  std::unordered_map<std::string, int> index_;
  std::vector<std::string> fields_;
  long line_ = 0;
};

/// Writes a CSV file (gzip when the path ends in `.gz`). Numbers are written in their shortest
/// exact form, so a recording is reproducible byte for byte and reads back to the same doubles.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& header);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  CsvWriter& add(double value);
  CsvWriter& add(const std::string& text);
  /// Ends the current row; throws when the row has the wrong number of fields.
  void end_row();
  void flush();
  const std::string& path() const { return path_; }

 private:
  void write(const char* data, std::size_t size);

  std::string path_;
  struct Sink;
  std::unique_ptr<Sink> sink_;
  std::size_t columns_;
  std::size_t fields_in_row_ = 0;
  std::string row_;
};

/// Shortest decimal text that reads back to exactly the same double ("nan", "inf" for non-finite).
std::string format_number(double value);

}  // namespace windfdi
