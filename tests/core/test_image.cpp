// PFM and PNG files and all-or-nothing outputs (techniques/core/image/image.h).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "error.h"
#include "image/image.h"

namespace fs = std::filesystem;
using namespace shadowlab;

namespace {

// A fresh folder per test, so tests can run in parallel processes (ctest -j).
std::string testDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    fs::path dir = fs::path(SHADOWLAB_TEST_TMP) / (std::string("image-") + info->test_suite_name() + "-" + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

uint32_t bitsOf(float f) {
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

float floatFromBits(uint32_t b) {
    float f;
    std::memcpy(&f, &b, 4);
    return f;
}

std::string littleEndian(float f) {
    uint32_t b = bitsOf(f);
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i) s[i] = char((b >> (8 * i)) & 0xFF);
    return s;
}

std::string bigEndian(float f) {
    uint32_t b = bitsOf(f);
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i) s[i] = char((b >> (8 * (3 - i))) & 0xFF);
    return s;
}

// Values that a careless writer would change: NaN with a payload, -0, infinities, a denormal.
Image trickyImage(int channels) {
    Image image(5, 3, channels);
    for (size_t i = 0; i < image.data.size(); ++i) image.data[i] = 0.1f * float(i) - 0.7f;
    image.data[1] = floatFromBits(0x7FC01234u);  // quiet NaN with payload
    image.data[2] = -0.0f;
    image.data[3] = std::numeric_limits<float>::infinity();
    image.data[4] = -std::numeric_limits<float>::infinity();
    image.data[5] = std::numeric_limits<float>::denorm_min();
    image.data.back() = std::numeric_limits<float>::quiet_NaN();
    return image;
}

void expectSameBits(const Image& a, const Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.channels, b.channels);
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) {
        EXPECT_EQ(bitsOf(a.data[i]), bitsOf(b.data[i])) << "value " << i;
    }
}

void expectInputError(const std::string& path, const std::string& expectedPart) {
    try {
        readPFM(path);
        FAIL() << "readPFM(" << path << ") accepted a bad file";
    } catch (const InputError& e) {
        std::string message = e.what();
        EXPECT_NE(message.find(path), std::string::npos) << "message does not name the file: " << message;
        EXPECT_NE(message.find(expectedPart), std::string::npos) << "message: " << message;
    }
}

}  // namespace

TEST(Pfm, RoundTripOneChannelKeepsEveryBit) {
    std::string path = testDir() + "/v.pfm";
    Image image = trickyImage(1);
    writePFM(path, image);
    expectSameBits(image, readPFM(path));
}

TEST(Pfm, RoundTripThreeChannelsKeepsEveryBit) {
    std::string path = testDir() + "/p.pfm";
    Image image = trickyImage(3);
    writePFM(path, image);
    expectSameBits(image, readPFM(path));
}

TEST(Pfm, FourChannelsAreWrittenAsThree) {
    std::string path = testDir() + "/rgba.pfm";
    Image image = trickyImage(4);
    writePFM(path, image);
    Image back = readPFM(path);
    ASSERT_EQ(back.channels, 3);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            for (int c = 0; c < 3; ++c) EXPECT_EQ(bitsOf(back.at(x, y, c)), bitsOf(image.at(x, y, c)));
        }
    }
}

// PFM stores rows bottom-to-top: the top-left pixel of the Image is the first value of the LAST
// row on disk.
TEST(Pfm, RowsAreStoredBottomToTop) {
    std::string path = testDir() + "/rows.pfm";
    Image image(4, 3, 1, 0.0f);
    image.at(0, 0) = 7.5f;   // top-left
    image.at(3, 2) = -2.0f;  // bottom-right
    writePFM(path, image);
    std::string bytes = readBytes(path);
    const std::string header = "Pf\n4 3\n-1.0\n";
    ASSERT_EQ(bytes.substr(0, header.size()), header);
    ASSERT_EQ(bytes.size(), header.size() + 4 * 3 * 4);
    const size_t rowBytes = 4 * 4;
    std::string lastRow = bytes.substr(header.size() + 2 * rowBytes, rowBytes);
    EXPECT_EQ(lastRow.substr(0, 4), littleEndian(7.5f));
    std::string firstRow = bytes.substr(header.size(), rowBytes);
    EXPECT_EQ(firstRow.substr(12, 4), littleEndian(-2.0f));
}

TEST(Pfm, ThreeChannelHeader) {
    std::string path = testDir() + "/rgb.pfm";
    writePFM(path, Image(2, 7, 3, 0.5f));
    std::string bytes = readBytes(path);
    EXPECT_EQ(bytes.substr(0, 12), "PF\n2 7\n-1.0\n");
    EXPECT_EQ(bytes.size(), 12u + 2 * 7 * 3 * 4);
}

TEST(Pfm, WritingIsDeterministic) {
    std::string dir = testDir();
    Image image = trickyImage(3);
    writePFM(dir + "/a.pfm", image);
    writePFM(dir + "/b.pfm", image);
    EXPECT_EQ(readBytes(dir + "/a.pfm"), readBytes(dir + "/b.pfm"));
}

TEST(Pfm, ReadsBigEndianFiles) {
    std::string path = testDir() + "/big.pfm";
    // A positive scale means big-endian; other tools' header spacing (all on one line) is fine.
    writeBytes(path, "Pf 2 2 1.0\n" + bigEndian(1.0f) + bigEndian(2.0f) + bigEndian(3.0f) + bigEndian(-4.5f));
    Image image = readPFM(path);
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 2);
    EXPECT_EQ(image.at(0, 1), 1.0f);  // first on disk = bottom row
    EXPECT_EQ(image.at(1, 1), 2.0f);
    EXPECT_EQ(image.at(0, 0), 3.0f);
    EXPECT_EQ(image.at(1, 0), -4.5f);
}

TEST(Pfm, BadFilesAreInputErrors) {
    std::string dir = testDir();
    const std::string pixel = littleEndian(0.25f);
    struct Case {
        std::string name, bytes, expected;
    };
    const Case cases[] = {
        {"empty.pfm", "", "expected \"Pf\""},
        {"ppm.pfm", "P6\n1 1\n255\n\x01\x02\x03", "expected \"Pf\""},
        {"nowidth.pfm", "Pf\n\n", "expected a width and a height"},
        {"negative.pfm", "Pf\n-1 1\n-1.0\n" + pixel, "expected a width and a height"},
        {"zero.pfm", "Pf\n0 1\n-1.0\n", "expected a width and a height"},
        {"letters.pfm", "Pf\n1x 1\n-1.0\n" + pixel, "expected a width and a height"},
        {"huge.pfm", "Pf\n99999999 99999999\n-1.0\n" + pixel, "expected a width and a height"},
        {"noscale.pfm", "Pf\n1 1\n", "expected a non-zero scale"},
        {"zeroscale.pfm", "Pf\n1 1\n0.0\n" + pixel, "expected a non-zero scale"},
        {"textscale.pfm", "Pf\n1 1\nabc\n" + pixel, "expected a non-zero scale"},
        {"truncated.pfm", "Pf\n2 2\n-1.0\n" + pixel + pixel + pixel, "truncated PFM data: expected 16 bytes"},
        {"truncated3.pfm", "PF\n1 1\n-1.0\n" + pixel + pixel, "truncated PFM data: expected 12 bytes"},
        {"nodata.pfm", "Pf\n1 1\n-1.0", "expected one whitespace character after the scale"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        std::string path = dir + "/" + c.name;
        writeBytes(path, c.bytes);
        expectInputError(path, c.expected);
    }
    expectInputError(dir + "/missing.pfm", "cannot read the PFM file: no such file");
}

TEST(Png, WritesAPngOfTheRightSizeDeterministically) {
    std::string dir = testDir();
    Image image(6, 4, 3, 0.25f);
    image.at(0, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    image.at(1, 0, 1) = 7.0f;
    image.at(2, 0, 2) = -1.0f;
    writePNG(dir + "/a.png", image);
    writePNG(dir + "/b.png", image);
    std::string bytes = readBytes(dir + "/a.png");
    ASSERT_GE(bytes.size(), 33u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(bytes.substr(12, 4), "IHDR");
    auto be32 = [&](size_t at) {
        return (uint32_t(uint8_t(bytes[at])) << 24) | (uint32_t(uint8_t(bytes[at + 1])) << 16) |
               (uint32_t(uint8_t(bytes[at + 2])) << 8) | uint32_t(uint8_t(bytes[at + 3]));
    };
    EXPECT_EQ(be32(16), 6u);
    EXPECT_EQ(be32(20), 4u);
    EXPECT_EQ(uint8_t(bytes[24]), 8);  // bit depth
    EXPECT_EQ(uint8_t(bytes[25]), 2);  // colour type RGB
    EXPECT_EQ(bytes, readBytes(dir + "/b.png"));
}

TEST(Png, GreyAndRgbaColourTypes) {
    std::string dir = testDir();
    writePNG(dir + "/grey.png", Image(3, 3, 1, 0.5f));
    writePNG(dir + "/rgba.png", Image(3, 3, 4, 0.5f));
    EXPECT_EQ(uint8_t(readBytes(dir + "/grey.png")[25]), 0);
    EXPECT_EQ(uint8_t(readBytes(dir + "/rgba.png")[25]), 6);
}

TEST(OutputSet, CommitMovesEveryTemporaryIntoPlace) {
    std::string dir = testDir();
    std::string a = dir + "/a.pfm";
    std::string b = dir + "/b.png";
    {
        OutputSet outputs;
        std::string ta = outputs.stage(a);
        std::string tb = outputs.stage(b);
        EXPECT_EQ(ta, a + ".tmp-" + std::to_string(::getpid()));
        EXPECT_EQ(outputs.stage(a), ta);  // staging twice gives the same temporary
        writePFM(ta, Image(2, 2, 1, 0.5f));
        writePNG(tb, Image(2, 2, 1, 0.5f));
        EXPECT_FALSE(fs::exists(a));
        EXPECT_FALSE(fs::exists(b));
        outputs.commit();
        EXPECT_TRUE(fs::exists(a));
        EXPECT_TRUE(fs::exists(b));
        EXPECT_FALSE(fs::exists(ta));
        EXPECT_FALSE(fs::exists(tb));
    }
    // Destroying a committed set removes nothing.
    EXPECT_TRUE(fs::exists(a));
    EXPECT_TRUE(fs::exists(b));
    EXPECT_EQ(readPFM(a).at(1, 1), 0.5f);
    size_t files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        (void)entry;
        ++files;
    }
    EXPECT_EQ(files, 2u);
}

TEST(OutputSet, AbortLeavesNoPartialOutput) {
    std::string dir = testDir();
    std::string fresh = dir + "/fresh.pfm";
    std::string existing = dir + "/existing.pfm";
    writePFM(existing, Image(1, 1, 1, 0.25f));  // from an earlier, successful run
    std::string tFresh;
    std::string tExisting;
    try {
        OutputSet outputs;
        tFresh = outputs.stage(fresh);
        tExisting = outputs.stage(existing);
        writePFM(tFresh, Image(2, 2, 1, 1.0f));
        writePFM(tExisting, Image(2, 2, 1, 1.0f));
        throw InputError("half-way failure");
    } catch (const InputError&) {
    }
    EXPECT_FALSE(fs::exists(fresh));
    EXPECT_FALSE(fs::exists(tFresh));
    EXPECT_FALSE(fs::exists(tExisting));
    ASSERT_TRUE(fs::exists(existing));
    EXPECT_EQ(readPFM(existing).at(0, 0), 0.25f);  // the old output is untouched
}

TEST(OutputSet, AbortWithUnwrittenTemporariesIsQuiet) {
    std::string dir = testDir();
    {
        OutputSet outputs;
        outputs.stage(dir + "/never-written.pfm");
    }
    EXPECT_TRUE(fs::is_empty(dir));
}

namespace {

size_t stagedFilesIn(const std::string& dir) {
    size_t n = 0;
    for (const auto& entry : fs::directory_iterator(dir)) n += entry.path().string().find(".tmp-") != std::string::npos;
    return n;
}

}  // namespace

// Issue 24: SIGTERM with more staged files than the first round's 64 signal slots. A child stages
// 150 written files and is killed; every temporary is gone (the first 64 only, before).
TEST(OutputSet, SigtermAfterMoreThan64StagedFilesRemovesThemAll) {
    const std::string dir = testDir();
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        removeStagedOutputsOnSignals();
        auto* outputs = new OutputSet;  // never destroyed: only the handler may clean up
        for (int i = 0; i < 150; ++i) writePFM(outputs->stage(dir + "/out-" + std::to_string(i) + ".pfm"), Image(1, 1, 1, 0.5f));
        (void)!::write(ready[1], "x", 1);
        while (true) ::pause();
    }
    ::close(ready[1]);
    char byte = 0;
    ASSERT_EQ(::read(ready[0], &byte, 1), 1);
    ::close(ready[0]);
    EXPECT_EQ(stagedFilesIn(dir), 150u);
    ::kill(child, SIGTERM);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
    EXPECT_EQ(stagedFilesIn(dir), 0u);
    EXPECT_TRUE(fs::is_empty(dir));
}

// Issue 24: commit() renames nothing when a final path is a folder (the PNG and PFM were moved into
// place before the sidecar's rename failed), and stage() refuses a folder that cannot take the file.
TEST(OutputSet, AFolderWhereAFileGoesCommitsNothing) {
    const std::string dir = testDir();
    fs::create_directories(dir + "/v.pfm.json");
    {
        OutputSet outputs;
        writePNG(outputs.stage(dir + "/o.png"), Image(2, 2, 1, 0.5f));
        writePFM(outputs.stage(dir + "/v.pfm"), Image(2, 2, 1, 0.5f));
        std::ofstream(outputs.stage(dir + "/v.pfm.json")) << "{}";
        try {
            outputs.commit();
            ADD_FAILURE() << "commit() moved files over a folder";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(dir + "/v.pfm.json: is a folder"), std::string::npos) << e.what();
        }
    }
    EXPECT_FALSE(fs::exists(dir + "/o.png"));
    EXPECT_FALSE(fs::exists(dir + "/v.pfm"));
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) entries += (void(e), 1);
    EXPECT_EQ(entries, 1u);  // the folder only
    OutputSet outputs;
    try {
        outputs.stage("/sys/shadowlab-test-output.png");
        ADD_FAILURE() << "staged a file in /sys";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/sys/shadowlab-test-output.png: cannot write the output in the folder '/sys'"),
                  std::string::npos)
            << e.what();
    }
}

// Issue 24: a PFM header is checked from the file's first bytes before the raster is read: a side
// over 8192 and a file far longer than its header says are refused at once, without reading a
// sparse gigabyte.
TEST(Pfm, AHeaderIsCheckedBeforeTheRasterIsRead) {
    const std::string dir = testDir();
    auto sparse = [&](const std::string& name, const std::string& header, uintmax_t size) {
        const std::string path = dir + "/" + name;
        std::ofstream(path, std::ios::binary) << header;
        fs::resize_file(path, size);
        return path;
    };
    const uintmax_t almostGiB = (uintmax_t(1) << 30) - 1;
    for (const auto& [path, message] : std::vector<std::pair<std::string, std::string>>{
             {sparse("huge.pfm", "Pf\n30000 30000\n-1.0\n", almostGiB), "expected a width and a height as positive integers up to 8192"},
             {sparse("long.pfm", "Pf\n16 16\n-1.0\n", almostGiB), "bytes follow it"},
             {sparse("short.pfm", "Pf\n8192 8192\n-1.0\n", 1000), "truncated PFM data"}}) {
        SCOPED_TRACE(path);
        const auto t0 = std::chrono::steady_clock::now();
        std::string error;
        try {
            readPFM(path);
        } catch (const InputError& e) {
            error = e.what();
        }
        EXPECT_NE(error.find(path), std::string::npos) << error;
        EXPECT_NE(error.find(message), std::string::npos) << error;
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.2);
    }
}
