// The page's own files (client/view/page), built into lpss-view so that it runs from anywhere.
#pragma once

#include <string_view>
#include <vector>

namespace lpss::view {

struct PageAsset {
    const char* path;  ///< the URL path, "/index.html"
    std::string_view content;
    const char* mime;
};

/// Made at build time by client/view/embed_page.cmake.
const std::vector<PageAsset>& page_assets();

}  // namespace lpss::view
