// A package held in memory (ContainerReader::openMemory): the same sections and bytes as from the
// file, borrowed in place or copied, and exactly the same errors as the file path for every
// truncation and every flipped byte. A borrowed buffer that is not 64-byte aligned is refused.

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <set>
#include <string>

#include "package/container_reader.h"
#include "package/container_writer.h"
#include "package_test_support.h"

namespace firelook::package {
namespace {

using test::asBytes;
using Ownership = ContainerReader::MemoryOwnership;

using test::kFactors;
const std::filesystem::path kName = "engine.pak:fire/explosion.firelook";

class MemorySource : public ::testing::Test {
  protected:
    void SetUp() override {
        path_ = dir_ / "good.firelook";
        ContainerWriter writer(path_);
        writer.addMetadata(R"({"tool":"memory source test"})");
        writer.addSection(kFactors, 0, asBytes(test::smoothFloats(100, 1)), Codec::Raw);
        writer.addSection(kFactors, 1, asBytes(test::smoothFloats(100, 2)), Codec::Zstd);
        writer.addSection(kFactors, 2, {}, Codec::Raw);
        writer.commit();
        good_ = test::readFile(path_);
    }

    // What opening and reading every section gives, as text: "ok" per section, or the error code;
    // the message must name `source` (so a memory source and a file differ only in the name).
    static std::string outcome(const std::function<ContainerReader()>& open, const std::filesystem::path& source) {
        const auto failure = [&](const PackageError& e) {
            EXPECT_EQ(e.file(), source);
            EXPECT_NE(std::string(e.what()).find(source.string()), std::string::npos) << e.what();
            return std::string(toString(e.code()));
        };
        std::string result;
        try {
            const ContainerReader reader = open();
            result = "open ok";
            for (const SectionInfo& section : reader.sections()) {
                try {
                    reader.read(section);
                    if (section.codec == Codec::Raw) reader.mapped(section);
                    result += ", ok";
                } catch (const PackageError& e) {
                    result += ", " + failure(e);
                }
            }
        } catch (const PackageError& e) {
            result = "open " + failure(e);
        }
        return result;
    }

    // The file's outcome and the memory outcomes, borrowed and copied, must be the same; returns it.
    std::string expectSameAsFile(std::span<const std::byte> bytes, const std::string& context) {
        SCOPED_TRACE(context);
        const auto file = dir_ / "crafted.firelook";
        test::writeFile(file, bytes);
        const std::string want = outcome([&] { return ContainerReader::open(file); }, file);
        const test::AlignedBytes held(bytes);
        for (const Ownership ownership : {Ownership::Borrow, Ownership::Copy})
            EXPECT_EQ(outcome([&] { return ContainerReader::openMemory(held.view(), ownership, kName); }, kName), want)
                << (ownership == Ownership::Borrow ? "borrowed" : "copied");
        return want;
    }

    test::TempDir dir_;
    std::filesystem::path path_;
    std::vector<std::byte> good_;
};

TEST_F(MemorySource, GoodBytesReadAsTheFileBorrowedInPlaceOrCopied) {
    const ContainerReader from_file = ContainerReader::open(path_);
    test::AlignedBytes held(good_);
    for (const Ownership ownership : {Ownership::Borrow, Ownership::Copy}) {
        SCOPED_TRACE(ownership == Ownership::Borrow ? "borrowed" : "copied");
        const ContainerReader reader = ContainerReader::openMemory(held.view(), ownership, kName);
        EXPECT_EQ(reader.file(), kName);
        EXPECT_EQ(reader.isBorrowed(), ownership == Ownership::Borrow);
        EXPECT_FALSE(reader.isMemoryMapped());
        EXPECT_EQ(reader.fileSize(), good_.size());
        EXPECT_EQ(reader.version(), from_file.version());
        EXPECT_EQ(reader.metadata(), from_file.metadata());
        ASSERT_EQ(reader.sections().size(), from_file.sections().size());
        for (size_t i = 0; i < reader.sections().size(); ++i) {
            EXPECT_EQ(reader.sections()[i], from_file.sections()[i]);
            EXPECT_EQ(reader.read(reader.sections()[i]), from_file.read(from_file.sections()[i])) << i;
        }
        // A raw section is a 64-byte aligned view: of the caller's bytes when borrowed, of a copy otherwise.
        const SectionInfo& raw = *reader.find(kFactors, 0);
        const std::span<const std::byte> view = reader.mapped(raw);
        EXPECT_EQ(reinterpret_cast<uintptr_t>(view.data()) % kSectionAlignment, 0u);
        EXPECT_EQ(view.data() == held.view().data() + raw.offset, ownership == Ownership::Borrow);
    }
    // A copy owes nothing to the caller's buffer once open returns.
    ContainerReader copied = ContainerReader::openMemory(held.view(), Ownership::Copy, kName);
    const std::vector<std::byte> want = copied.read(*copied.find(kFactors, 1));
    std::memset(held.bytes().data(), 0xA5, held.bytes().size());
    const ContainerReader moved = std::move(copied);
    EXPECT_EQ(moved.read(*moved.find(kFactors, 1)), want);
    EXPECT_EQ(moved.metadata(), from_file.metadata());
}

// Borrowing is chosen to avoid a second copy, so a buffer the reader cannot use in place is refused
// with a message that says why and what to do, before any byte is read; copying accepts any alignment.
TEST_F(MemorySource, ABorrowedBufferThatIsNot64ByteAlignedIsRefusedAndACopyIsAligned) {
    for (size_t misalignment = 1; misalignment < kSectionAlignment; ++misalignment) {
        const test::AlignedBytes held(good_, misalignment);
        ASSERT_EQ(reinterpret_cast<uintptr_t>(held.view().data()) % kSectionAlignment, misalignment);
        try {
            ContainerReader::openMemory(held.view(), Ownership::Borrow, kName);
            ADD_FAILURE() << "misalignment " << misalignment << " was accepted";
        } catch (const PackageError& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
            EXPECT_EQ(e.file(), kName);
            const std::string message = e.what();
            EXPECT_NE(message.find("64-byte aligned"), std::string::npos) << message;
            EXPECT_NE(message.find(std::to_string(misalignment) + " bytes past"), std::string::npos) << message;
        }
        const ContainerReader copied = ContainerReader::openMemory(held.view(), Ownership::Copy, kName);
        const std::span<const std::byte> view = copied.mapped(*copied.find(kFactors, 0));
        EXPECT_EQ(reinterpret_cast<uintptr_t>(view.data()) % kSectionAlignment, 0u) << misalignment;
    }
    // Garbage that is also misaligned: the alignment, a caller's mistake, is reported first.
    const std::vector<std::byte> garbage(100, std::byte{0x42});
    const test::AlignedBytes held(garbage, 8);
    test::expectPackageError([&] { ContainerReader::openMemory(held.view(), Ownership::Borrow, kName); },
                             ErrorCode::InvalidArgument, kName);
}

TEST_F(MemorySource, EmptyBytesAreNotAPackage) {
    for (const Ownership ownership : {Ownership::Borrow, Ownership::Copy}) {
        test::expectPackageError([&] { ContainerReader::openMemory({}, ownership, kName); }, ErrorCode::NotAPackage,
                                 kName);
    }
}

TEST_F(MemorySource, TruncatedAtEveryLengthGivesTheFilesError) {
    std::set<std::string> seen;
    for (size_t length = 0; length < good_.size(); ++length) {
        seen.insert(expectSameAsFile(std::span(good_).first(length), "length " + std::to_string(length)));
        if (::testing::Test::HasFailure()) return;  // one length is enough to read
    }
    EXPECT_EQ(seen, (std::set<std::string>{"open not a FireLook package", "open truncated"}));
}

TEST_F(MemorySource, AFlippedByteAnywhereGivesTheFilesError) {
    std::set<std::string> seen;
    for (size_t offset = 0; offset < good_.size(); ++offset) {
        std::vector<std::byte> bytes = good_;
        bytes[offset] ^= std::byte{0x10};
        seen.insert(expectSameAsFile(bytes, "byte " + std::to_string(offset)));
        if (::testing::Test::HasFailure()) return;
    }
    // The sweep reaches every kind of outcome: identifier, major, header and index, one section, padding.
    for (const char* kind : {"open not a FireLook package", "open newer major version", "open corrupt",
                             "open ok, corrupt, ok, ok, ok", "open ok, ok, corrupt, ok, ok", "open ok, ok, ok, ok, ok"})
        EXPECT_EQ(seen.count(kind), 1u) << kind;
}

}  // namespace
}  // namespace firelook::package
