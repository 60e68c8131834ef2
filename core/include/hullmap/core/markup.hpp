#pragma once

#include <string>

namespace hullmap::core {

/// `text` with &, <, > and " as character references: safe as the text of an HTML, SVG or XML
/// element and inside a double-quoted attribute.
std::string escapeMarkup(const std::string& text);

}  // namespace hullmap::core
