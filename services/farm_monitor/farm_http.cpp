// The farm monitor's web server (cpp-httplib).
#include "farm_http.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <fstream>
#include <sstream>

#include "yaml_config.hpp"

namespace windfdi::farm {

namespace {

std::string content_type(const std::string& name) {
  const auto dot = name.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : name.substr(dot + 1);
  if (ext == "html") return "text/html; charset=utf-8";
  if (ext == "js") return "text/javascript; charset=utf-8";
  if (ext == "css") return "text/css; charset=utf-8";
  if (ext == "map") return "application/json";
  return "application/octet-stream";
}

// A file of Debian's packaged JavaScript below `root`, for a path below /js/: plain names only, nothing
// outside the directory.
bool packaged_file(const std::string& root, const std::string& path, std::string& content) {
  const std::string rest = path.substr(4);
  if (rest.empty() || rest.find("..") != std::string::npos) return false;
  for (char c : rest)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '/' || c == '.' || c == '_' || c == '-'))
      return false;
  std::ifstream in(root + "/" + rest, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  content = s.str();
  return true;
}

void send(httplib::Response& res, const ApiResponse& r) {
  res.status = r.status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(r.body, r.content_type.c_str());
}

}  // namespace

std::string read_token(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file, 0, "--http-token-file", "cannot read the operator token file");
  std::ostringstream s;
  s << in.rdbuf();
  std::string token = s.str();
  const auto first = token.find_first_not_of(" \t\r\n");
  const auto last = token.find_last_not_of(" \t\r\n");
  if (first == std::string::npos) throw ConfigError(file, 1, "--http-token-file", "the token file is empty");
  token = token.substr(first, last - first + 1);
  if (token.find_first_of(" \t\r\n") != std::string::npos)
    throw ConfigError(file, 1, "--http-token-file", "the token must be one word");
  return token;
}

FarmHttp::FarmHttp(const HttpOptions& options, FarmApi& api) {
  // "PORT" or "ADDR:PORT" (an IPv6 address in brackets).
  std::string host = "127.0.0.1", port_text = options.listen;
  const auto colon = options.listen.rfind(':');
  if (colon != std::string::npos) {
    host = options.listen.substr(0, colon);
    port_text = options.listen.substr(colon + 1);
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  }
  int port = -1;
  try {
    std::size_t used = 0;
    port = std::stoi(port_text, &used);
    if (used != port_text.size()) port = -1;
  } catch (const std::exception&) {
    port = -1;
  }
  if (host.empty() || port < 0 || port > 65535)
    throw ConfigError("--http", 0, "", "'" + options.listen + "' is not PORT or ADDR:PORT");

  const bool tls = !options.cert.empty() || !options.key.empty();
  if (tls) {
    if (options.cert.empty() || options.key.empty())
      throw ConfigError("--http-cert", 0, "", "HTTPS needs both --http-cert and --http-key");
    auto ssl = std::make_unique<httplib::SSLServer>(options.cert.c_str(), options.key.c_str());
    if (!ssl->is_valid())
      throw ConfigError(options.cert, 0, "--http-cert", "certificate or key " + options.key + " not usable");
    server_ = std::move(ssl);
  } else {
    server_ = std::make_unique<httplib::Server>();
  }
  httplib::Server& svr = *server_;
  svr.set_payload_max_length(64 * 1024);
  // A slow or stalled client holds one of the server's threads for at most these, never the DDS loop.
  svr.set_read_timeout(5, 0);
  svr.set_write_timeout(5, 0);
  svr.set_keep_alive_timeout(5);

  const auto serve = [&api, root = options.javascript_dir](const httplib::Request& req,
                                                           httplib::Response& res) {
    if (req.method == "GET") {
      const WebAsset page = web_asset(req.path == "/" ? "/index.html" : req.path);
      if (page.content) {
        res.set_header("X-Content-Type-Options", "nosniff");
        res.set_content(page.content, content_type(page.name).c_str());
        return;
      }
      std::string file;
      if (req.path.rfind("/js/", 0) == 0) {
        if (packaged_file(root, req.path, file)) {
          res.set_header("X-Content-Type-Options", "nosniff");
          res.set_content(file, content_type(req.path).c_str());
        } else {
          send(res, api_error(404, "no packaged JavaScript at " + req.path + " (libjs-dygraphs installed?)"));
        }
        return;
      }
    }
    ApiRequest r;
    r.method = req.method;
    r.path = req.path;
    for (const auto& [key, value] : req.params) r.params[key] = value;
    r.body = req.body;
    r.remote_addr = req.remote_addr;
    r.authorization = req.get_header_value("Authorization");
    send(res, api.handle(r));
  };
  svr.Get(".*", serve);
  svr.Post(".*", serve);
  const auto refuse = [](const httplib::Request& req, httplib::Response& res) {
    send(res, api_error(405, "method " + req.method + " not allowed on " + req.path));
  };
  svr.Put(".*", refuse);
  svr.Delete(".*", refuse);
  svr.Patch(".*", refuse);
  // Whatever httplib itself refuses (a malformed request line, a body past the limit) gets a JSON error too.
  svr.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty())
      send(res, api_error(res.status, "request refused (HTTP " + std::to_string(res.status) + ")"));
  });
  svr.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "internal error";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    send(res, api_error(500, what));
  });

  const int bound = port == 0 ? svr.bind_to_any_port(host) : (svr.bind_to_port(host, port) ? port : -1);
  if (bound < 0) throw ConfigError("--http", 0, "", "cannot listen on " + options.listen);
  const bool v6 = host.find(':') != std::string::npos;
  url_ = std::string(tls ? "https" : "http") + "://" + (v6 ? "[" + host + "]" : host) + ":" +
         std::to_string(bound) + "/";
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  spdlog::info("farm monitor: web page and API on {}", url_);
}

FarmHttp::~FarmHttp() {
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace windfdi::farm
