// The walk mirrors OpenVDB 10's readers step by step (io/Archive.cc, io/File.cc, io/GridDescriptor.cc,
// Metadata.h, io/DelayedLoadMetadata.cc, math/Maps.h, tree/RootNode.h, tree/InternalNode.h,
// tree/LeafNode.h, io/Compression.h/.cc); each function names the one it stands for.
#include "vdb/file_structure.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string_view>
#include <vector>

#include "vdb/vdb_error.h"

namespace firelook::vdb {
namespace {

constexpr int64_t kMagic = 0x56444220;   // OPENVDB_MAGIC, "VDB " in the first 8 bytes
constexpr uint32_t kOldestVersion = 222;  // OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION (OpenVDB 2.0)
constexpr uint32_t kNewestVersion = 224;  // OPENVDB_FILE_VERSION of OpenVDB 10
static_assert(kNewestVersion == openvdb::OPENVDB_FILE_VERSION, "review this check for the new format");

// io::COMPRESS_* flags.
constexpr uint32_t kZip = 0x1, kActiveMask = 0x2, kBlosc = 0x4;

// The float tree OpenVDB reads for FloatGrid: root -> internal (2^5 per axis) -> internal (2^4) ->
// leaf (2^3). Masks are one bit per slot.
constexpr const char* kFloatTreeType = "Tree_float_5_4_3";
constexpr const char* kHalfFloatSuffix = "_HalfFloat";
constexpr uint32_t kLeafValues = 512;
constexpr uint32_t kLeafMaskBytes = kLeafValues / 8;
constexpr int32_t kRootChildDim = 1 << (5 + 4 + 3);  // extent of a root child, in voxels

// The fixed payload size of each metadata type openvdb::initialize() registers (Metadata.h:
// TypedMetadata<T>::readValue reads sizeof(T) whatever the file says, so the two must agree).
constexpr std::array<std::pair<std::string_view, uint32_t>, 16> kFixedMetadata{{
    {"bool", 1}, {"int32", 4}, {"int64", 8}, {"float", 4}, {"double", 8}, {"vec2i", 8}, {"vec2s", 8},
    {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16}, {"vec4s", 16}, {"vec4d", 32},
    {"mat4s", 64}, {"mat4d", 128},
}};

// The bytes each affine-like map's read() consumes (math/Maps.h): Mat4d; or Vec3d fields.
constexpr std::array<std::pair<std::string_view, uint32_t>, 7> kMapSizes{{
    {"AffineMap", 128}, {"UnitaryMap", 128}, {"ScaleMap", 5 * 24}, {"UniformScaleMap", 5 * 24},
    {"TranslationMap", 24}, {"ScaleTranslateMap", 6 * 24}, {"UniformScaleTranslateMap", 6 * 24},
}};
constexpr std::string_view kFrustumMap = "NonlinearFrustumMap";  // BBoxd, taper, depth, second map

template <std::size_t N>
const uint32_t* lookUp(const std::array<std::pair<std::string_view, uint32_t>, N>& table, std::string_view key) {
    for (const auto& [name, size] : table)
        if (name == key) return &size;
    return nullptr;
}

// A bounded cursor over the file's bytes; every failure names the file, the part and the offset.
class Cursor {
  public:
    Cursor(std::span<const std::byte> file, const std::string& name) : file_(file), name_(name), end_(file.size()) {}

    uint64_t position() const { return position_; }
    uint64_t left() const { return end_ - position_; }
    const std::byte* at(uint64_t offset) const { return file_.data() + offset; }
    const std::string& scope() const { return scope_; }
    void setScope(std::string scope) { scope_ = std::move(scope); }

    // Continues at `offset` with reads bounded by `end` (both already checked against the file).
    void moveTo(uint64_t offset, uint64_t end) {
        position_ = offset;
        end_ = end;
    }

    [[noreturn]] void fail(const std::string& problem) const {
        throw VdbError(name_ + ": not a readable VDB file: " + (scope_.empty() ? "" : scope_ + ": ") + problem +
                       " (at byte " + std::to_string(position_) + ")");
    }

    void need(uint64_t bytes, std::string_view what) const {
        if (bytes > left()) {
            fail(std::string(what) + " needs " + std::to_string(bytes) + " bytes but " + std::to_string(left()) +
                 (end_ == file_.size() ? " are left in the file" : " are left in its part of the file"));
        }
    }

    template <typename T>
    T read(std::string_view what) {
        need(sizeof(T), what);
        T value;
        std::memcpy(&value, at(position_), sizeof(T));
        position_ += sizeof(T);
        return value;
    }

    const std::byte* take(uint64_t bytes, std::string_view what) {
        need(bytes, what);
        const std::byte* start = at(position_);
        position_ += bytes;
        return start;
    }

    void skip(uint64_t bytes, std::string_view what) { take(bytes, what); }

    // io::readString: a uint32 length, then the characters.
    std::string string(std::string_view what) {
        const uint32_t length = read<uint32_t>(what);
        need(length, std::string(what) + " (" + std::to_string(length) + " characters)");
        std::string text(reinterpret_cast<const char*>(at(position_)), length);
        position_ += length;
        return text;
    }

  private:
    std::span<const std::byte> file_;
    const std::string& name_;
    std::string scope_;
    uint64_t position_ = 0;
    uint64_t end_;
};

template <typename T>
T load(const std::byte* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

uint32_t countOn(const std::byte* mask, uint32_t bytes) {
    uint32_t count = 0;
    for (uint32_t i = 0; i < bytes; i += 8) count += static_cast<uint32_t>(std::popcount(load<uint64_t>(mask + i)));
    return count;
}

// blosc 1.x's 16-byte header (blosc.h): version, versionlz, flags, typesize, nbytes, blocksize,
// cbytes; then, unless the buffer is a plain copy, one int32 start offset per block. blosc_decompress
// trusts cbytes and the offsets, so they must lie inside the chunk OpenVDB read.
// `expected` is the size OpenVDB decompresses into; a larger `up_to` allows a writer's padding.
void checkBloscChunk(const Cursor& in, const std::byte* chunk, uint64_t size, uint64_t expected, std::string_view what,
                     uint64_t up_to = 0) {
    constexpr uint64_t kHeader = 16;
    constexpr uint8_t kMemcpyed = 0x2;
    if (size < kHeader) in.fail(std::string(what) + ": blosc chunk of " + std::to_string(size) + " bytes is shorter than its header");
    const auto flags = static_cast<uint8_t>(chunk[2]);
    const uint32_t nbytes = load<uint32_t>(chunk + 4), blocksize = load<uint32_t>(chunk + 8),
                   cbytes = load<uint32_t>(chunk + 12);
    if (nbytes < expected || nbytes > std::max(expected, up_to))
        in.fail(std::string(what) + ": blosc chunk decompresses to " + std::to_string(nbytes) + " bytes, " +
                std::to_string(expected) + (up_to > expected ? " to " + std::to_string(up_to) : std::string()) +
                " expected");
    if (cbytes != size)
        in.fail(std::string(what) + ": blosc header says " + std::to_string(cbytes) + " compressed bytes, the chunk has " +
                std::to_string(size));
    if (flags & kMemcpyed) {
        if (cbytes < kHeader + nbytes) in.fail(std::string(what) + ": blosc copy chunk shorter than its data");
        return;
    }
    if (nbytes == 0) return;
    if (blocksize == 0 || blocksize > nbytes) in.fail(std::string(what) + ": blosc block size " + std::to_string(blocksize) + " is invalid");
    const uint64_t blocks = (uint64_t{nbytes} + blocksize - 1) / blocksize;
    const uint64_t table_end = kHeader + 4 * blocks;
    if (table_end > cbytes) in.fail(std::string(what) + ": blosc block table exceeds the chunk");
    for (uint64_t b = 0; b < blocks; ++b) {
        const auto start = load<int32_t>(chunk + kHeader + 4 * b);
        if (start < 0 || static_cast<uint64_t>(start) < table_end || static_cast<uint64_t>(start) >= cbytes)
            in.fail(std::string(what) + ": blosc block " + std::to_string(b) + " starts outside the chunk");
    }
}

// io::readData: a zip or blosc chunk (int64 size, negative for stored bytes) or raw values.
void checkData(Cursor& in, uint64_t expected, uint32_t compression, std::string_view what) {
    if (!(compression & (kZip | kBlosc))) {
        in.skip(expected, what);
        return;
    }
    const auto size = in.read<int64_t>(what);
    if (size <= 0) {
        // io::unzipFromStream / bloscFromStream copy -size bytes into a buffer of `expected`
        // bytes before they compare the two (the heap overflow in tests/fuzz/crashes/).
        if (size == std::numeric_limits<int64_t>::min() || static_cast<uint64_t>(-size) != expected) {
            in.fail(std::string(what) + " holds " + (size == std::numeric_limits<int64_t>::min() ? "an invalid number of" : std::to_string(-size)) +
                    " stored bytes, " + std::to_string(expected) + " expected");
        }
        in.skip(expected, what);
        return;
    }
    const std::byte* chunk = in.take(static_cast<uint64_t>(size), what);
    if (compression & kBlosc) checkBloscChunk(in, chunk, static_cast<uint64_t>(size), expected, what);
}

struct TreeFormat {
    uint32_t compression = 0;
    uint64_t value_bytes = 4;  // float, or 2 for half-float storage
    bool half = false;
};

// io::readCompressedValues: a flag byte, inactive values and a selection mask as the flag says,
// then the values (only the active ones under mask compression).
void checkCompressedValues(Cursor& in, const TreeFormat& tree, uint32_t count, const std::byte* value_mask,
                           uint32_t mask_bytes, std::string_view what) {
    const auto flag = in.read<int8_t>(what);
    enum : int8_t { kNoMaskOrInactive, kNoMaskMinusBg, kNoMaskOneInactive, kMaskNoInactive, kMaskOneInactive,
                    kMaskTwoInactive, kNoMaskAllValues };
    if (flag < kNoMaskOrInactive || flag > kNoMaskAllValues)
        in.fail(std::string(what) + ": unknown value compression flag " + std::to_string(flag));
    if (flag == kNoMaskOneInactive || flag == kMaskOneInactive || flag == kMaskTwoInactive) in.skip(4, what);
    if (flag == kMaskTwoInactive) in.skip(4, what);
    if (flag == kMaskNoInactive || flag == kMaskOneInactive || flag == kMaskTwoInactive) in.skip(mask_bytes, what);
    uint32_t stored = count;
    if ((tree.compression & kActiveMask) && flag != kNoMaskAllValues) stored = countOn(value_mask, mask_bytes);
    if (tree.half && stored == 0) return;  // HalfReader reads nothing for no values
    checkData(in, stored * tree.value_bytes, tree.compression, what);
}

// InternalNode::readTopology (level 2: 32^3 slots of level-1 nodes; level 1: 16^3 slots of leaves),
// LeafNode::readTopology (the value mask). Leaf masks are collected in reading order, which is
// also the order their buffers follow.
void checkInternalTopology(Cursor& in, const TreeFormat& tree, int level, std::vector<uint64_t>& leaf_masks) {
    const uint32_t slots = level == 2 ? 32768u : 4096u;
    const uint32_t mask_bytes = slots / 8;
    const std::byte* child_mask = in.take(mask_bytes, "internal node child mask");
    const std::byte* value_mask = in.take(mask_bytes, "internal node value mask");
    checkCompressedValues(in, tree, slots, value_mask, mask_bytes, "internal node values");
    const uint32_t children = countOn(child_mask, mask_bytes);
    if (level == 1) {
        in.need(uint64_t{children} * kLeafMaskBytes, "leaf masks");
        for (uint32_t i = 0; i < children; ++i)
            leaf_masks.push_back(static_cast<uint64_t>(in.take(kLeafMaskBytes, "leaf mask") - in.at(0)));
        return;
    }
    // Each level-1 child holds at least its two masks and a flag byte.
    in.need(uint64_t{children} * (2 * 512 + 1), "internal node children");
    for (uint32_t i = 0; i < children; ++i) checkInternalTopology(in, tree, 1, leaf_masks);
}

struct Key {
    int32_t x, y, z;
    auto operator<=>(const Key&) const = default;
};

// Tree::readTopology: TreeBase's buffer count; then RootNode::readTopology: background, tile and
// child counts, tiles (origin, value, active), then children (origin, topology). OpenVDB keys its
// table by the origins as read and later reads the buffers in the table's (sorted) order; a writer
// writes sorted, aligned, unique origins, and this requires them so that file order and buffer
// order agree and no node is dropped.
void checkRootTopology(Cursor& in, const TreeFormat& tree, std::vector<uint64_t>& leaf_masks) {
    in.skip(4, "tree buffer count");  // TreeBase::readTopology (always 1; OpenVDB only warns otherwise)
    in.skip(4, "background value");
    const auto tiles = in.read<uint32_t>("root tile count");
    const auto children = in.read<uint32_t>("root child count");
    in.need(uint64_t{tiles} * 17, "root tiles");
    in.need(uint64_t{children} * 12, "root children");
    std::vector<Key> keys;
    keys.reserve(std::size_t{tiles} + children);
    const auto readKey = [&](const char* what) {
        const Key key{in.read<int32_t>(what), in.read<int32_t>(what), in.read<int32_t>(what)};
        for (const int32_t c : {key.x, key.y, key.z})
            if (c % kRootChildDim != 0)
                in.fail(std::string(what) + " (" + std::to_string(key.x) + ", " + std::to_string(key.y) + ", " +
                        std::to_string(key.z) + ") is not a multiple of " + std::to_string(kRootChildDim));
        keys.push_back(key);
        return key;
    };
    for (uint32_t i = 0; i < tiles; ++i) {
        readKey("root tile origin");
        in.skip(4, "root tile value");
        if (std::to_integer<unsigned>(*in.take(1, "root tile state")) > 1) in.fail("root tile active flag is neither 0 nor 1");
    }
    for (uint32_t i = 0; i < children; ++i) {
        const Key key = readKey("root child origin");
        if (i > 0 && !(keys[keys.size() - 2] < key)) in.fail("root children are not in strictly increasing order");
        checkInternalTopology(in, tree, 2, leaf_masks);
    }
    std::sort(keys.begin(), keys.end());
    if (std::adjacent_find(keys.begin(), keys.end()) != keys.end()) in.fail("two root nodes share an origin");
}

// LeafNode::readBuffers for each leaf: its value mask again (OpenVDB skips it and uses the
// topology's, so the two must agree), then its 512 values.
void checkBuffers(Cursor& in, const TreeFormat& tree, const std::vector<uint64_t>& leaf_masks) {
    for (std::size_t i = 0; i < leaf_masks.size(); ++i) {
        const std::byte* mask = in.take(kLeafMaskBytes, "leaf buffer mask");
        if (std::memcmp(mask, in.at(leaf_masks[i]), kLeafMaskBytes) != 0)
            in.fail("leaf " + std::to_string(i) + "'s buffer mask differs from its topology mask");
        checkCompressedValues(in, tree, kLeafValues, mask, kLeafMaskBytes, "leaf values");
    }
}

// io::DelayedLoadMetadata::readValue: leaf count; a mask array (blosc or stored); an optional
// compressed-size array (blosc, stored, or absent as 0xFFFFFFFF); unknown trailing bytes skipped.
// OpenVDB allocates both arrays for `count` entries, so the count is bounded by the leaves the
// grid's bytes can hold (a leaf takes at least two 64-byte masks). Writers pad the compressed
// arrays (12 sizes stored as 16 in the bundled sample); OpenVDB sizes its buffer from the padded
// length, which is bounded here to twice the array.
void checkDelayedLoadMetadata(Cursor& in, uint32_t size, uint64_t max_leaves) {
    if (size == 0) return;
    const uint64_t start = in.position();
    const auto count = in.read<uint32_t>("delayed-load metadata");
    if (count > max_leaves)
        in.fail("delayed-load metadata claims " + std::to_string(count) + " leaves; the grid has room for " +
                std::to_string(max_leaves));
    const auto array = [&](uint32_t bytes, uint64_t element) {
        const uint64_t expected = uint64_t{count} * element;
        if (bytes == 0) {
            in.skip(expected, "delayed-load metadata array");
            return;
        }
        checkBloscChunk(in, in.take(bytes, "delayed-load metadata array"), bytes, expected, "delayed-load metadata array",
                        2 * expected + 256);
    };
    array(in.read<uint32_t>("delayed-load metadata"), 1);
    const auto sizes = in.read<uint32_t>("delayed-load metadata");
    if (sizes != std::numeric_limits<uint32_t>::max()) array(sizes, 8);
    const uint64_t used = in.position() - start;
    if (used > size) in.fail("delayed-load metadata is longer (" + std::to_string(used) + " bytes) than its size " + std::to_string(size));
    in.skip(size - used, "delayed-load metadata");
}

// MetaMap::readMeta / Metadata::read: count, then (name, type name, size, value) per item.
void checkMetadata(Cursor& in, const char* what, uint64_t max_leaves) {
    const auto count = in.read<uint32_t>(what);
    in.need(uint64_t{count} * 12, what);  // each item: two string lengths and a size at least
    for (uint32_t i = 0; i < count; ++i) {
        const std::string name = in.string("metadata name");
        const std::string type = in.string("metadata type name");
        const auto size = in.read<uint32_t>("metadata size");
        const std::string item = std::string(what) + " item '" + name + "' (" + type + ")";
        if (const uint32_t* fixed = lookUp(kFixedMetadata, type)) {
            if (size != *fixed) in.fail(item + " has " + std::to_string(size) + " bytes, " + std::to_string(*fixed) + " expected");
            const std::byte* value = in.take(size, item);
            if (type == "bool" && std::to_integer<unsigned>(*value) > 1) in.fail(item + " is neither 0 nor 1");
        } else if (type == "__delayedload") {
            in.need(size, item);
            checkDelayedLoadMetadata(in, size, max_leaves);
        } else if (type == "string" || !openvdb::Metadata::isRegisteredType(type)) {
            in.skip(size, item);  // a string, or UnknownMetadata: the raw bytes
        } else {
            in.fail(item + " has a registered type this check does not know");
        }
    }
}

// Transform::read and MapBase::read.
void checkTransform(Cursor& in) {
    const std::string type = in.string("transform map type");
    if (const uint32_t* size = lookUp(kMapSizes, type)) {
        in.skip(*size, type);
        return;
    }
    if (type != kFrustumMap) in.fail("unknown transform map type '" + type + "'");
    in.skip(48 + 8 + 8, type);
    const std::string second = in.string("frustum's second map type");
    const uint32_t* size = lookUp(kMapSizes, second);
    if (!size) in.fail("frustum's second map has an unsupported type '" + second + "'");
    in.skip(*size, second);
}

struct Descriptor {
    std::string name;
    std::string type;  // without the half-float suffix
    std::string parent;
    bool half = false;
    uint64_t grid = 0, blocks = 0, end = 0;
};

// Archive::readGrid for a grid OpenVDB may be asked to read: compression, metadata, transform; and
// for a float tree the topology, which must end where the blocks begin, and the buffers, which
// must end where the grid ends.
void checkGrid(Cursor& in, const Descriptor& grid) {
    in.setScope("grid '" + grid.name + "'");
    in.moveTo(grid.grid, grid.end);
    TreeFormat tree;
    tree.compression = in.read<uint32_t>("grid compression flags");
    if (tree.compression & ~(kZip | kActiveMask | kBlosc)) in.fail("unknown compression flags " + std::to_string(tree.compression));
    tree.half = grid.half;
    tree.value_bytes = grid.half ? 2 : 4;
    checkMetadata(in, "grid metadata", (grid.end - grid.grid) / (2 * kLeafMaskBytes));
    checkTransform(in);
    if (!grid.parent.empty() || grid.type != kFloatTreeType) {
        // An instance has no tree of its own; other trees are never read (see file_structure.h).
        if (in.position() > grid.blocks) in.fail("metadata and transform run past the grid's data blocks");
        return;
    }
    std::vector<uint64_t> leaf_masks;
    in.moveTo(in.position(), grid.blocks);
    checkRootTopology(in, tree, leaf_masks);
    if (in.position() != grid.blocks)
        in.fail("the tree topology ends " + std::to_string(grid.blocks - in.position()) + " bytes before the data blocks");
    in.moveTo(grid.blocks, grid.end);
    checkBuffers(in, tree, leaf_masks);
    if (in.position() != grid.end) in.fail("the leaf buffers end " + std::to_string(grid.end - in.position()) + " bytes before the grid");
}

void checkUuid(Cursor& in) {
    const std::byte* uuid = in.take(36, "file UUID");
    int hyphens = 0;
    for (int i = 0; i < 36; ++i) {
        const char c = static_cast<char>(uuid[i]);
        if (c == '-') {
            ++hyphens;
        } else if (!std::isxdigit(static_cast<unsigned char>(c))) {
            in.fail("the file UUID holds a character that is neither a hex digit nor '-'");
        }
    }
    if (hyphens != 4) in.fail("the file UUID has " + std::to_string(hyphens) + " hyphens, 4 expected");
}

// Archive::readHeader, File::open (file metadata) and File::readGridDescriptors, then each grid.
void checkFile(std::span<const std::byte> bytes, const std::string& name) {
    openvdb::initialize();  // metadata types are looked up in OpenVDB's registry; idempotent
    Cursor in(bytes, name);
    if (bytes.empty()) in.fail("the file is empty");
    if (bytes.size() < 8 || load<int64_t>(bytes.data()) != kMagic) in.fail("no OpenVDB magic number");
    in.skip(8, "magic number");
    const auto version = in.read<uint32_t>("file format version");
    if (version < kOldestVersion)
        in.fail("file format version " + std::to_string(version) + " predates " + std::to_string(kOldestVersion) +
                " (OpenVDB 2.0); re-save it with a newer OpenVDB");
    if (version > kNewestVersion)
        in.fail("file format version " + std::to_string(version) + " is newer than this reader's (" +
                std::to_string(kNewestVersion) + ", OpenVDB 10)");
    in.skip(8, "library version");
    const auto offsets = std::to_integer<unsigned>(*in.take(1, "grid offsets flag"));
    if (offsets > 1) in.fail("grid offsets flag is neither 0 nor 1");
    if (offsets == 0) in.fail("the file has no grid offsets (an OpenVDB stream, not a file); re-save it with io::File");
    checkUuid(in);
    checkMetadata(in, "file metadata", bytes.size() / (2 * kLeafMaskBytes));
    const auto count = in.read<int32_t>("grid count");
    if (count < 0) in.fail("negative grid count " + std::to_string(count));
    in.need(uint64_t(count) * 36, "grid descriptors");  // three string lengths and three offsets each

    std::vector<Descriptor> grids;
    for (int32_t i = 0; i < count; ++i) {
        Descriptor grid;
        in.setScope("grid descriptor " + std::to_string(i));
        grid.name = in.string("grid name");
        grid.type = in.string("grid type");
        if (grid.type.ends_with(kHalfFloatSuffix)) {
            grid.half = true;
            grid.type.resize(grid.type.size() - std::strlen(kHalfFloatSuffix));
        }
        grid.parent = in.string("instance parent name");
        const auto grid_pos = in.read<int64_t>("grid offset");
        const auto blocks_pos = in.read<int64_t>("data block offset");
        const auto end_pos = in.read<int64_t>("grid end offset");
        // An instance has no data blocks; io::File leaves its block offset 0.
        const bool no_blocks = !grid.parent.empty() && blocks_pos == 0;
        if (end_pos >= 0 && static_cast<uint64_t>(end_pos) > bytes.size())
            in.fail("grid '" + grid.name + "' ends at byte " + std::to_string(end_pos) + ", past the end of the file (" +
                    std::to_string(bytes.size()) + " bytes): truncated?");
        if (grid_pos < static_cast<int64_t>(in.position()) || end_pos < grid_pos ||
            (!no_blocks && (blocks_pos < grid_pos || end_pos < blocks_pos)) ||
            static_cast<uint64_t>(end_pos) > bytes.size()) {
            in.fail("offsets " + std::to_string(grid_pos) + ", " + std::to_string(blocks_pos) + ", " + std::to_string(end_pos) +
                    " (grid, data blocks, end) are not increasing from the end of the descriptor");
        }
        grid.grid = static_cast<uint64_t>(grid_pos);
        grid.blocks = static_cast<uint64_t>(no_blocks ? end_pos : blocks_pos);
        grid.end = static_cast<uint64_t>(end_pos);
        grids.push_back(grid);
        in.moveTo(grid.end, bytes.size());  // the next descriptor follows this grid
    }
    for (const Descriptor& grid : grids) {
        if (!grid.parent.empty()) {
            // Reading an instance reads its parent's tree (the parent is checked as a grid itself).
            const auto parent = std::find_if(grids.begin(), grids.end(), [&](const Descriptor& g) { return g.name == grid.parent; });
            if (parent == grids.end() || parent->type != grid.type || !parent->parent.empty()) {
                in.setScope("grid '" + grid.name + "'");
                in.fail("instance of '" + grid.parent + "', which is missing, of another type or an instance itself");
            }
        }
        checkGrid(in, grid);
    }
}

}  // namespace

void checkFileStructure(std::span<const std::byte> bytes, const std::string& name) { checkFile(bytes, name); }

void checkFileStructure(const std::filesystem::path& file) {
    const std::string name = file.string();
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw VdbError(ErrorCode::IoError, name + ": cannot open: " + std::strerror(errno));
    struct stat status {};
    if (::fstat(fd, &status) != 0) {
        const int error = errno;
        ::close(fd);
        throw VdbError(ErrorCode::IoError, name + ": cannot read its size: " + std::strerror(error));
    }
    const auto size = static_cast<std::size_t>(status.st_size);
    if (size == 0) {
        ::close(fd);
        checkFile({}, name);
        return;
    }
    // Mapped, not read: the walk touches the headers of every chunk but not the data between them,
    // and the pages it touches are the ones OpenVDB reads next.
    void* mapped = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    const int error = errno;
    ::close(fd);
    if (mapped == MAP_FAILED)
        throw VdbError(ErrorCode::IoError, name + ": cannot map the file: " + std::strerror(error));
    struct Unmap {
        void* data;
        std::size_t size;
        ~Unmap() { ::munmap(data, size); }
    } unmap{mapped, size};
    checkFile({static_cast<const std::byte*>(mapped), size}, name);
}

}  // namespace firelook::vdb
