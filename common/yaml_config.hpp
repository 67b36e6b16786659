// YAML configuration helpers: typed keys with defaults and range checks, errors that name file, line and key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace windfdi {

/// A configuration or input-file error. Executables catch it and exit with code 2.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, long line, const std::string& key, const std::string& message)
      : std::runtime_error(format(file, line, key, message)), file_(file), line_(line), key_(key) {}

  const std::string& file() const { return file_; }
  long line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  static std::string format(const std::string& file, long line, const std::string& key,
                            const std::string& message) {
    std::string s = file;
    if (line > 0) s += ":" + std::to_string(line);
    if (!key.empty()) s += ": key '" + key + "'";
    return s + ": " + message;
  }
  std::string file_;
  long line_;
  std::string key_;
};

/// A YAML mapping together with the file it came from and the dotted path leading to it,
/// so every error can say where it is.
class YamlSection {
 public:
  YamlSection(YAML::Node node, std::string file, std::string path = "")
      : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

  /// Loads a YAML file; a missing file or a syntax error is a ConfigError.
  static YamlSection load_file(const std::string& file) {
    try {
      YAML::Node root = YAML::LoadFile(file);
      if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
      if (!root.IsMap()) throw ConfigError(file, root.Mark().line + 1, "", "top level must be a mapping");
      return YamlSection(root, file);
    } catch (const YAML::BadFile&) {
      throw ConfigError(file, 0, "", "cannot open file");
    } catch (const YAML::ParserException& e) {
      throw ConfigError(file, e.mark.line + 1, "", "YAML syntax error: " + e.msg);
    }
  }

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }
  std::string key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  int line() const { return node_.Mark().line + 1; }
  bool has(const std::string& key) const {
    return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
  }

  /// Fails on any key not in `allowed`, listing the valid choices (a typo must not fall back to a default).
  void require_known_keys(const std::set<std::string>& allowed) const {
    if (!node_.IsMap()) throw error("", "must be a mapping");
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (allowed.count(key)) continue;
      std::string choices;
      for (const auto& a : allowed) choices += (choices.empty() ? "" : ", ") + a;
      throw ConfigError(file_, kv.first.Mark().line + 1, key_path(key),
                        "unknown key (valid keys: " + choices + ")");
    }
  }

  /// A sub-mapping; missing gives an empty one so nested defaults still apply.
  YamlSection section(const std::string& key) const {
    if (!has(key)) return YamlSection(YAML::Node(YAML::NodeType::Map), file_, key_path(key));
    const YAML::Node n = node_[key];
    if (!n.IsMap()) throw ConfigError(file_, n.Mark().line + 1, key_path(key), "must be a mapping");
    return YamlSection(n, file_, key_path(key));
  }

  /// The elements of a sequence of mappings, each as a section named key[i].
  std::vector<YamlSection> sequence(const std::string& key) const {
    std::vector<YamlSection> out;
    if (!has(key)) return out;
    const YAML::Node n = node_[key];
    if (!n.IsSequence()) throw ConfigError(file_, n.Mark().line + 1, key_path(key), "must be a list");
    for (std::size_t i = 0; i < n.size(); ++i)
      out.emplace_back(n[i], file_, key_path(key) + "[" + std::to_string(i) + "]");
    return out;
  }

  /// A typed value, or `fallback` when the key is absent. A value of the wrong type is an error.
  template <class T>
  T get(const std::string& key, const T& fallback) const {
    if (!has(key)) return fallback;
    return as<T>(key);
  }

  /// A typed value that must be present.
  template <class T>
  T require(const std::string& key) const {
    if (!has(key)) throw error(key, "required key is missing");
    return as<T>(key);
  }

  /// A finite number within [min, max], or `fallback` when absent.
  double get_number(const std::string& key, double fallback, double min, double max) const {
    const double v = get<double>(key, fallback);
    check_range(key, v, min, max);
    return v;
  }

  double require_number(const std::string& key, double min, double max) const {
    const double v = require<double>(key);
    check_range(key, v, min, max);
    return v;
  }

  /// A file name, or `fallback` when the key is absent; a relative name is taken beside this YAML file (so a
  /// configuration and the files it names move together, e.g. to /etc/windfdi).
  std::string get_path(const std::string& key, const std::string& fallback) const {
    if (!has(key)) return fallback;
    const std::filesystem::path f = as<std::string>(key);
    return f.is_relative() ? (std::filesystem::path(file_).parent_path() / f).string() : f.string();
  }

  /// One of a fixed set of strings.
  std::string get_choice(const std::string& key, const std::string& fallback,
                         const std::set<std::string>& choices) const {
    const std::string v = get<std::string>(key, fallback);
    if (!choices.count(v)) {
      std::string list;
      for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
      throw error(key, "'" + v + "' is not one of: " + list);
    }
    return v;
  }

  ConfigError error(const std::string& key, const std::string& message) const {
    const int line = (!key.empty() && has(key)) ? node_[key].Mark().line + 1 : this->line();
    return ConfigError(file_, line, key.empty() ? path_ : key_path(key), message);
  }

 private:
  template <class T>
  T as(const std::string& key) const {
    try {
      return node_[key].as<T>();
    } catch (const YAML::Exception&) {
      throw error(key, "value '" + YAML::Dump(node_[key]) + "' has the wrong type");
    }
  }

  void check_range(const std::string& key, double v, double min, double max) const {
    if (!std::isfinite(v) || v < min || v > max)
      throw error(key, "value " + std::to_string(v) + " is outside [" + std::to_string(min) + ", " +
                           std::to_string(max) + "]");
  }

  YAML::Node node_;
  std::string file_;
  std::string path_;
};

}  // namespace windfdi
