#pragma once
// Characters that print as nothing, which make two names or paths that read the same in every
// log, status line and listing differ: refused in campaign names and output paths.
#include <cstdio>
#include <string>
#include <string_view>

namespace jamsim {

/// "U+200B" when `text` (UTF-8) holds a character that prints as nothing: C1 controls, the
/// soft hyphen, the zero-width space, direction marks and embeddings, line and paragraph
/// separators, Hangul fillers, the byte-order mark; else "".
inline std::string invisible_character(std::string_view text) {
    for (std::size_t k = 0; k < text.size();) {
        const auto byte = static_cast<unsigned char>(text[k]);
        const std::size_t length = byte < 0x80 ? 1 : byte >= 0xF0 ? 4 : byte >= 0xE0 ? 3 : byte >= 0xC0 ? 2 : 1;
        if (length == 1 || k + length > text.size()) {
            ++k;
            continue;
        }
        char32_t code = byte & (0xFF >> (length + 1));
        for (std::size_t b = 1; b < length; ++b) code = (code << 6) | (static_cast<unsigned char>(text[k + b]) & 0x3F);
        k += length;
        // Not the zero-width (non-)joiners U+200C and U+200D: Persian and Indic names need them.
        const bool invisible = (code >= 0x80 && code <= 0x9F) || code == 0xAD || code == 0x34F || code == 0x61C ||
                               code == 0x115F || code == 0x1160 || code == 0x180E || code == 0x200B ||
                               (code >= 0x200E && code <= 0x200F) || (code >= 0x2028 && code <= 0x202E) ||
                               (code >= 0x2060 && code <= 0x206F) || code == 0x3164 || code == 0xFEFF || code == 0xFFA0;
        if (invisible) {
            char name[16];
            std::snprintf(name, sizeof name, "U+%04X", static_cast<unsigned>(code));
            return name;
        }
    }
    return "";
}

}  // namespace jamsim
