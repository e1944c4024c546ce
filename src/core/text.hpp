#pragma once
// Strict number parsing for file readers: the whole token must be a number.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tactus::text {

std::optional<double> to_double(std::string_view token);
std::optional<std::int64_t> to_int(std::string_view token);

/// Splits on spaces and tabs (and a trailing carriage return); empty tokens are dropped.
std::vector<std::string_view> split(std::string_view line);

std::string_view trim(std::string_view s);

/// `s` as a JSON string literal: quotes and backslashes escaped, control characters as `\uXXXX`.
std::string json_quoted(std::string_view s);

}  // namespace tactus::text
