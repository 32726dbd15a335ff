// The payload of an animation over the WebSocket (FrameKind::animation,
// API.md): the artifact's .frames bytes (core/animation.h) with every frame
// after the first replaced by its difference from the one before (uint16,
// modulo 65536: the quantized deltas of small steps are small numbers), the
// whole compressed with zlib (RFC 1950).  Undoing it gives the .frames bytes
// back exactly.
#pragma once

#include <string>
#include <string_view>

namespace cgview::protocol {

// Throws InvalidInput for bytes that are not a .frames file.
std::string encode_animation_payload(std::string_view frames_bytes);
// The .frames bytes again; throws InvalidInput for a corrupt payload or one
// that does not inflate to raw_bytes.
std::string decode_animation_payload(std::string_view payload, std::size_t raw_bytes);

}  // namespace cgview::protocol
