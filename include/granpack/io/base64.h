#pragma once
// Base64 (RFC 4648, with padding): binary state inside JSON text, e.g. the event-driven
// engine's saved state in a checkpoint's /run_state (docs/long-jobs.md).
#include <cstdint>
#include <string>
#include <vector>

namespace granpack {

std::string base64_encode(const std::vector<std::uint8_t>& bytes);
/// Throws std::invalid_argument on a character outside the alphabet or a bad length.
std::vector<std::uint8_t> base64_decode(const std::string& text);

} // namespace granpack
