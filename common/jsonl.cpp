// JSON Lines writer.
#include "jsonl.hpp"

#include <cerrno>
#include <cstring>

#include "yaml_config.hpp"

namespace windfdi {

JsonlWriter::JsonlWriter(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "w")) {
  if (!file_) throw ConfigError(path, 0, "", std::string("cannot create: ") + std::strerror(errno));
}

JsonlWriter::~JsonlWriter() {
  if (file_) std::fclose(file_);
}

void JsonlWriter::write(const nlohmann::json& object) {
  const std::string line = object.dump() + "\n";
  if (std::fwrite(line.data(), 1, line.size(), file_) != line.size() || std::fflush(file_) != 0)
    throw std::runtime_error(path_ + ": write failed");
}

}  // namespace windfdi
