// JSON Lines writer: one JSON object per line, flushed per line so a crash loses nothing written.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace windfdi {

class JsonlWriter {
 public:
  explicit JsonlWriter(const std::string& path);
  ~JsonlWriter();
  JsonlWriter(const JsonlWriter&) = delete;
  JsonlWriter& operator=(const JsonlWriter&) = delete;
  void write(const nlohmann::json& object);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_;
};

}  // namespace windfdi
