#pragma once
// A check of a .vdb file's structure before OpenVDB parses it.
//
// OpenVDB 10's reader trusts the sizes a file gives: a string or chunk length read from a damaged
// or hostile file is allocated or copied as is (tests/fuzz/README.md lists what that did: multi-GB
// allocations, a 25 s string append, a heap overflow in io::unzipFromStream). This check walks
// everything OpenVDB will read (header, file and grid metadata, grid descriptors, transforms and,
// for float grids, the whole tree: root tiles and children, internal node masks and values, leaf
// masks and buffers) and verifies every count, length and offset against the file (and every
// uncompressed or blosc chunk's length against the size OpenVDB will copy it into) without
// decompressing anything. openVdbFile runs it before every open.
//
// Accepted: format versions 222 (OpenVDB 2.0) to 224 (OpenVDB 10), files written by io::File (with
// grid offsets), zip, blosc, active-mask and no compression, half-float storage, instanced grids.
// Grids of other value types are checked up to their transform (their trees are never read:
// frame loading refuses a non-float grid from its metadata).

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

namespace firelook::vdb {

// Throws VdbError "<file>: not a readable VDB file: <problem> (at byte N)" for the first inconsistency,
// or when the file cannot be read.
void checkFileStructure(const std::filesystem::path& file);

// The same check of a file's bytes; `name` stands for the file in messages.
void checkFileStructure(std::span<const std::byte> bytes, const std::string& name);

}  // namespace firelook::vdb
