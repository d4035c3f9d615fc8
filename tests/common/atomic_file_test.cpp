// common/atomic_file.h: the temporary's name and mode, concurrent writers of one target (threads
// and processes), and failures that must leave the previous file intact and no temporary behind.
#include "common/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "../support/temp_dir.h"
#include "common/error.h"

namespace firelook {
namespace {

using firelook::testing::TempDir;

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// A file that proves it is whole: "<writer> <length>\n" then that many copies of one letter.
std::string content(int writer, int round) {
    const std::size_t length = 50'000 + static_cast<std::size_t>(writer * 997 + round * 31) % 20'000;
    const std::string head = std::to_string(writer) + " " + std::to_string(length) + "\n";
    return head + std::string(length, static_cast<char>('a' + (writer + round) % 26));
}

bool isWhole(const std::string& text) {
    const std::size_t newline = text.find('\n');
    if (newline == std::string::npos) return false;
    const std::size_t space = text.find(' ');
    const std::size_t length = std::stoul(text.substr(space + 1, newline - space - 1));
    if (text.size() != newline + 1 + length) return false;
    return text.find_first_not_of(text.back(), newline + 1) == std::string::npos;
}

TEST(AtomicFile, TemporaryIsHiddenBesideTheTargetAndUniqueThenRenamed) {
    TempDir dir;
    const ::mode_t old_mask = ::umask(022);
    AtomicFile first(dir / "out.json");
    AtomicFile second(dir / "out.json");
    ::umask(old_mask);
    for (const AtomicFile* file : {&first, &second}) {
        const std::string name = file->temporary().filename().string();
        EXPECT_EQ(file->temporary().parent_path(), dir.path());
        EXPECT_TRUE(name.starts_with(".out.json." + std::to_string(::getpid()) + "-")) << name;
        EXPECT_TRUE(name.ends_with(".tmp")) << name;
    }
    EXPECT_NE(first.temporary(), second.temporary());
    first.write(std::string_view("first"));
    first.commit();
    EXPECT_TRUE(first.committed());
    EXPECT_EQ(first.fd(), -1);
    EXPECT_EQ(readText(dir / "out.json"), "first");
    struct stat status {};
    ASSERT_EQ(::stat((dir / "out.json").c_str(), &status), 0);
    EXPECT_EQ(status.st_mode & 0777, 0644u) << "mode 0666 less the umask, like any new file";
    second.discard();
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.json"});
}

TEST(AtomicFile, ConcurrentThreadsNeverCollideAndReadersOnlySeeWholeFiles) {
    TempDir dir;
    const std::filesystem::path target = dir / "report.json";
    writeFileAtomically(target, content(99, 0));
    std::atomic<bool> done{false};
    std::atomic<int> failures{0}, reads{0};
    std::thread reader([&] {
        while (!done) {
            if (!isWhole(readText(target))) ++failures;
            ++reads;
        }
    });
    std::vector<std::thread> writers;
    for (int w = 0; w < 6; ++w) {
        writers.emplace_back([&, w] {
            for (int round = 0; round < 40; ++round) writeFileAtomically(target, content(w, round));
        });
    }
    for (std::thread& writer : writers) writer.join();
    done = true;
    reader.join();
    EXPECT_EQ(failures, 0) << "a reader saw a partial file in " << reads << " reads";
    EXPECT_TRUE(isWhole(readText(target)));
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"report.json"}) << "no temporary left";
}

TEST(AtomicFile, ConcurrentProcessesNeverCollide) {
    TempDir dir;
    const std::filesystem::path target = dir / "frame.exr";
    std::vector<pid_t> children;
    for (int w = 0; w < 4; ++w) {
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            int status = 0;
            try {
                for (int round = 0; round < 30; ++round) writeFileAtomically(target, content(w, round));
            } catch (...) {
                status = 1;
            }
            ::_exit(status);
        }
        children.push_back(child);
    }
    for (const pid_t child : children) {
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a writer failed";
    }
    EXPECT_TRUE(isWhole(readText(target)));
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.exr"});
}

TEST(AtomicFile, AnExceptionWhileWritingKeepsThePreviousFileAndNoTemporary) {
    TempDir dir;
    const std::filesystem::path target = dir / "image.png";
    writeFileAtomically(target, std::string_view("previous"));
    EXPECT_THROW(writeFileAtomically(target,
                                     [](const std::filesystem::path& temporary) {
                                         std::ofstream(temporary) << "half of it";
                                         throw std::runtime_error("the image writer failed");
                                     }),
                 std::runtime_error);
    {
        AtomicFile abandoned(target);
        abandoned.write(std::string_view("never committed"));
    }  // destroyed without commit, as when an exception unwinds
    EXPECT_EQ(readText(target), "previous");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"image.png"});
}

TEST(AtomicFile, AFailedRenameOrCreateIsAnIoErrorNamingTheTarget) {
    TempDir dir;
    // A non-empty folder under the target's name: the rename fails after the data was written.
    std::filesystem::create_directories(dir / "taken" / "inside");
    try {
        writeFileAtomically(dir / "taken", std::string_view("bytes"));
        FAIL() << "no error";
    } catch (const Error& error) {
        EXPECT_EQ(error.code(), ErrorCode::IoError);
        EXPECT_NE(std::string(error.what()).find((dir / "taken").string() + ": cannot rename onto the target"),
                  std::string::npos)
            << error.what();
    }
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken"}) << "no temporary left";
    EXPECT_TRUE(std::filesystem::is_directory(dir / "taken" / "inside"));

    try {
        writeFileAtomically(dir / "missing" / "out.json", std::string_view("bytes"));
        FAIL() << "no error";
    } catch (const Error& error) {
        EXPECT_EQ(error.code(), ErrorCode::IoError);
        EXPECT_NE(std::string(error.what()).find("out.json: cannot create a temporary file beside it"), std::string::npos)
            << error.what();
    }
}

TEST(AtomicFile, WritesThroughTheDescriptorAreCommitted) {
    TempDir dir;
    AtomicFile file(dir / "package.bin");
    ASSERT_GE(file.fd(), 0);
    ASSERT_EQ(::write(file.fd(), "0123456789", 10), 10);
    ASSERT_EQ(::pwrite(file.fd(), "AB", 2, 0), 2);  // the package writer patches its header last
    file.commit();
    EXPECT_EQ(readText(dir / "package.bin"), "AB23456789");
    EXPECT_THROW(file.commit(), Error);
}

}  // namespace
}  // namespace firelook
