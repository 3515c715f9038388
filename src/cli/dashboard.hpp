// The browser dashboard (web/, docs/dashboard.md), embedded at build time by
// cmake/embed_assets.cmake into a generated .cpp: rangekit serve answers it at "/".
#pragma once

#include <span>

#include "rangekit/web/server.hpp"

namespace rangekit::cli {

// Empty when built with -DRANGEKIT_DASHBOARD=OFF.
std::span<const web::StaticAsset> dashboard_assets();

}  // namespace rangekit::cli
