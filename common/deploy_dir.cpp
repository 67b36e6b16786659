// deploy_dir(): the source tree when built, the installed configuration otherwise.
#include "deploy_dir.hpp"

#include <cstdlib>
#include <filesystem>

#ifndef WINDFDI_SOURCE_DEPLOY_DIR
#define WINDFDI_SOURCE_DEPLOY_DIR ""
#endif
#ifndef WINDFDI_INSTALL_CONFIG_DIR
#define WINDFDI_INSTALL_CONFIG_DIR "/etc/windfdi"
#endif

namespace windfdi {

std::string deploy_dir() {
  if (const char* d = std::getenv("WINDFDI_DEPLOY_DIR"); d && *d) return d;
  const std::string source = WINDFDI_SOURCE_DEPLOY_DIR;
  // An installed binary on another machine has no source tree: it reads what the package installed.
  if (!source.empty() && std::filesystem::is_directory(source)) return source;
  return WINDFDI_INSTALL_CONFIG_DIR;
}

}  // namespace windfdi
