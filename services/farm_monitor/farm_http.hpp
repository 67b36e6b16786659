// The farm monitor's web server: the page (compiled in), the packaged plotting library and the JSON API
// (core/farm_api.hpp) on cpp-httplib's own threads, never on the DDS loop.
#pragma once

#include <memory>
#include <string>
#include <thread>

#include "farm_api.hpp"

namespace httplib {
class Server;
}

namespace windfdi::farm {

struct HttpOptions {
  std::string listen;      ///< "PORT" (on 127.0.0.1) or "ADDR:PORT"; "" no web server; port 0: any free port
  std::string token_file;  ///< file holding the operator token ("" none: no acknowledgement, localhost only)
  std::string cert, key;   ///< PEM certificate and private key: HTTPS instead of HTTP
  std::string javascript_dir = "/usr/share/javascript";  ///< Debian's packaged JavaScript (libjs-dygraphs)
};

/// One compiled-in file of the page (content nullptr: none at that path).
struct WebAsset {
  const char* content;
  std::string name;
};
/// The page's file at a URL path ("/farm.js"); generated from services/farm_monitor/web/ by embed_web.cmake.
WebAsset web_asset(const std::string& path);

/// The operator token from a file (surrounding white space removed); throws ConfigError naming the file
/// when it cannot be read or is empty.
std::string read_token(const std::string& file);

class FarmHttp {
 public:
  /// Binds (throws ConfigError naming --http when the address is malformed or cannot be bound) and serves
  /// on a thread of its own until destroyed.
  FarmHttp(const HttpOptions& options, FarmApi& api);
  ~FarmHttp();
  FarmHttp(const FarmHttp&) = delete;
  FarmHttp& operator=(const FarmHttp&) = delete;
  /// The address served, e.g. "http://127.0.0.1:8080/".
  const std::string& url() const { return url_; }

 private:
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  std::string url_;
};

}  // namespace windfdi::farm
