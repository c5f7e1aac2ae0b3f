#pragma once
// Text placed inside the report's HTML: escaped element text, and JSON that can sit inside a
// <script> element without ending it.
#include <string>

#include <nlohmann/json.hpp>

namespace varsfm {

// The HTML/SVG-safe text of `text` (&, <, >, " and ' escaped).
std::string EscapeHtml(const std::string& text);

// `value` as JSON with every '<' written as \u003c, so that no "</script>" (an image named so)
// can close the element that carries it; '<' only occurs inside JSON strings, where the escape
// means the same character.
std::string JsonForScript(const nlohmann::json& value);

}  // namespace varsfm
