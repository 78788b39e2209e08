#pragma once
// Strict text-to-number parsing for files and options that people write: the whole text,
// decimal (std::from_chars: no leading space or '+', no hexadecimal), in the type's range.

#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>

namespace jamsim {

/// The whole of `text` as a T; false for trailing text ("1-2"), overflow ("1e999") or none.
template <typename T> bool parse_whole_text(std::string_view text, T& value) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc{} && end == text.data() + text.size();
}

/// As parse_whole_text, and finite ("inf" and "nan" parse but are refused).
inline bool parse_finite(std::string_view text, double& value) {
    return parse_whole_text(text, value) && std::isfinite(value);
}

/// True when the whole of `text` is a decimal number beyond a double's range ("1e400",
/// "1e-400"): such a text deserves its own words, not "a number".
inline bool decimal_beyond_double(std::string_view text) {
    if (text.starts_with('+') && text.size() > 1 && text[1] != '-') text.remove_prefix(1);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc::result_out_of_range && end == text.data() + text.size();
}

/// What a double-valued option or key allows when its text is beyond a double's range.
inline constexpr const char* kDoubleRangeWords =
    "a number within a double's range (about 1e-308 to 1e308 in magnitude, or 0)";

}  // namespace jamsim
