#pragma once
// The workbench page (serve/page/: index.html, app.js, style.css), compiled into the binary by
// serve/EmbedPage.cmake: no files to install, no CDN, no build step.
#include <string_view>
#include <vector>

namespace fp::serve {

struct PageAsset {
    std::string_view path;         //!< as requested: "/", "/app.js", "/style.css"
    std::string_view contentType;  //!< without the charset: every file is UTF-8
    std::string_view body;
};

const std::vector<PageAsset>& pageAssets();

}  // namespace fp::serve
