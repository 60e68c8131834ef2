#pragma once

namespace hullmap::view::detail {

/// The page's own files (view/src/viewer/*.js joined into one script, viewer.css, error_hook.js),
/// compiled in by view/embed_assets.cmake.
extern const char* const kViewerScript;
extern const char* const kViewerCss;
extern const char* const kErrorHook;

}  // namespace hullmap::view::detail
