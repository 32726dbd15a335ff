// Keyed, reversible scrambling of a mesh by chaotic sequences (after the
// permutation-substitution image ciphers the CGView paper cites: Jia 2010,
// Wang et al. 2007).  Teaching and research code, NOT vetted cryptography:
// see docs/CHAOS.md.
//
// Exactness: on the float32 coordinates.  Every coordinate is first rounded
// to float32 (what binary PLY, STL, glTF and the GPU store; a mesh read from
// such a file is unchanged by it), and decrypt(encrypt(M, key), key) gives
// those float32 values back bit for bit (-0.0 and denormals included), the
// faces exactly (same corners, same order).  Normals, UVs and colours are
// dropped.
//
// The cipher, all from one ChaoticStream seeded by SHA-256("encrypt", key):
//   1. the n vertices plus two header vertices holding the float32 bounding
//      box corners (lo, hi) are permuted (n + 2 vertices out);
//   2. the y and z coordinates are shuffled again, among the n non-header
//      slots, by two more permutations (x, y, z of a cipher vertex come from
//      three different plain vertices);
//   3. each coordinate is substituted: its rank among the float32 values of
//      [lo_a, hi_a] (an integer in [0, N_a)) becomes
//      (rank + keystream + previous cipher rank) mod N_a: a bijection onto
//      the same float range, so the cipher stays finite and inside the box;
//   4. the faces are permuted, their indices remapped, and each face's
//      corners rotated (orientation kept).
// The header vertices are stored as they are (the box is visible in the
// cipher anyway).  A wrong key reads other vertices as the box and gives an
// unrecognizable mesh, not an error: the cipher carries no key check.
#pragma once

#include <string>

#include "core/mesh.h"

namespace cgview::chaos {

// Throws InvalidInput: an empty key ("parameter 'key'"), no vertices, a
// non-finite coordinate, or more than 2^32 - 3 vertices.
Mesh encrypt(const Mesh& plain, const std::string& key);
// The inverse with the right key; any mesh of >= 2 vertices is accepted
// (a wrong key or a mesh that was not encrypted gives garbage, not an
// error).  Throws InvalidInput for an empty key or fewer than 2 vertices.
Mesh decrypt(const Mesh& cipher, const std::string& key);

// The plain mesh as encrypt sees it: positions rounded to float32, faces as
// they are, no attributes.  decrypt(encrypt(m)) == float32_copy(m) exactly.
Mesh float32_copy(const Mesh& m);

}  // namespace cgview::chaos
