#include "pipeline/timing/dram_banks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <map>
#include <random>
#include <vector>

namespace patchsim {
namespace {

DramBankConfig banksOf(int banks, std::uint32_t rowBytes) {
    DramBankConfig c;
    c.banks = banks;
    c.rowBytes = rowBytes;
    c.activateCycles = 10;
    c.prechargeCycles = 12;
    c.activateToActivateCycles = 3;
    return c;
}

// 256 lines of 64 bytes in address order over 4 banks of 1 KiB rows: 16 rows, each opened once
// (4 a bank), every other access a row hit. Worked by hand at 256 bytes a clock: a bank's first
// activation costs t_rcd = 10, each later one t_rp + t_rcd = 22, and its 64 lines a quarter cycle
// each: 10 + 3 x 22 + 16 = 92 cycles, above the bus's 256 x 0.25 = 64 and 16 activations x
// t_rrd = 48. At 32 bytes a clock the bus's 512 cycles are the longest.
TEST(DramBanks, ASequentialStreamOpensEachRowOnce) {
    DramBanks fastBus(banksOf(4, 1024), 256.0, 1), slowBus(banksOf(4, 1024), 32.0, 1);
    for (std::uint64_t line = 0; line < 256; ++line) {
        fastBus.access(line * 64, 64, 0);
        slowBus.access(line * 64, 64, 0);
    }
    EXPECT_EQ(fastBus.stats().transfers, 256u);
    EXPECT_EQ(fastBus.stats().activations, 16u);
    EXPECT_EQ(fastBus.stats().rowHits, 240u);
    EXPECT_DOUBLE_EQ(fastBus.patchTimes()[0].cycles, 92.0);
    EXPECT_EQ(fastBus.patchTimes()[0].limit, DramLimit::Bank);
    EXPECT_DOUBLE_EQ(slowBus.patchTimes()[0].cycles, 512.0);
    EXPECT_EQ(slowBus.patchTimes()[0].limit, DramLimit::Bus);
}

// Two rows of one bank in turn: every access reopens a row. 10 accesses: 10 + 9 x 22 + 10 x 2.
TEST(DramBanks, TwoRowsOfOneBankInTurnActivateOnEveryAccess) {
    DramBanks banks(banksOf(4, 1024), 32.0, 1);
    const std::uint64_t sameBankNextRow = 4 * 1024;
    for (int i = 0; i < 10; ++i) banks.access(i % 2 ? sameBankNextRow : 0, 64, 0);
    EXPECT_EQ(banks.stats().activations, 10u);
    EXPECT_EQ(banks.stats().rowHits, 0u);
    EXPECT_DOUBLE_EQ(banks.patchTimes()[0].cycles, 228.0);
}

// A new row at every access, alternating between two banks: the banks overlap their
// activations, so with a large t_rrd the activations' spacing is what limits: 40 x t_rrd =
// 40 x 30 = 1200 cycles, against each bank's 10 + 19 x 22 + 20 x 2 = 468.
TEST(DramBanks, ActivationsAcrossBanksAreSpacedByTrrd) {
    DramBankConfig c = banksOf(2, 1024);
    c.activateToActivateCycles = 30;
    DramBanks banks(c, 32.0, 1);
    // Chunks 0, 1 (banks 0, 1, row 0), then 2, 3 (row 1), ...: every access a new row.
    for (std::uint64_t chunk = 0; chunk < 40; ++chunk) banks.access(chunk * 1024, 64, 0);
    EXPECT_EQ(banks.stats().activations, 40u);
    EXPECT_DOUBLE_EQ(banks.patchTimes()[0].cycles, 1200.0);
    EXPECT_EQ(banks.patchTimes()[0].limit, DramLimit::Activations);
}

// Two channels, interleaved every 256 bytes: a sequential stream splits evenly and runs at the
// whole bus's rate (64 lines x 2 cycles = 128); a stream that stays in channel 0 runs at its half
// of the bus (32 lines x 4 cycles = 128 for half the bytes).
TEST(DramBanks, ChannelsShareTheBusAndAStreamOnOneChannelGetsItsShare) {
    DramBankConfig c = banksOf(4, 1024);
    c.channels = 2;
    c.activateCycles = c.prechargeCycles = c.activateToActivateCycles = 0;
    DramBanks even(c, 32.0, 1), oneChannel(c, 32.0, 1);
    for (std::uint64_t line = 0; line < 64; ++line) even.access(line * 64, 64, 0);
    EXPECT_DOUBLE_EQ(even.patchTimes()[0].cycles, 128.0);
    for (std::uint64_t line = 0; line < 64; ++line)
        if (line * 64 % 512 < 256) oneChannel.access(line * 64, 64, 0);
    EXPECT_EQ(oneChannel.stats().transfers, 32u);
    EXPECT_DOUBLE_EQ(oneChannel.patchTimes()[0].cycles, 128.0);
    // Channel 0's 32 lines in its own address order are 2 KiB: rows 0 of banks 0 and 1.
    EXPECT_EQ(oneChannel.stats().activations, 2u);
}

// A stride of channels x channel_bytes lands on one channel every time with the linear mapping,
// and on both in turn with the XOR mapping (run 2i folds to the parity of i): 64 lines at the
// channel's 4 cycles a line take 256 cycles, or 128. A stride of banks x row_bytes reopens rows
// of bank 0 only (linear: 10 + 7 x 22 + 8 x 2 = 180) or of every bank in turn (XOR: each bank
// opens two rows, 10 + 22 + 2 x 2 = 36).
TEST(DramBanks, TheXorMappingSpreadsStridesThatCampOnOneChannelOrBank) {
    DramBankConfig c = banksOf(4, 1024);
    c.channels = 2;
    c.activateCycles = c.prechargeCycles = c.activateToActivateCycles = 0;
    DramBankConfig hashed = c;
    hashed.mapping = DramMapping::Xor;
    DramBanks linear(c, 32.0, 1), xored(hashed, 32.0, 1);
    for (std::uint64_t i = 0; i < 64; ++i) {
        linear.access(i * 512, 64, 0);
        xored.access(i * 512, 64, 0);
    }
    EXPECT_DOUBLE_EQ(linear.patchTimes()[0].cycles, 256.0);
    EXPECT_DOUBLE_EQ(xored.patchTimes()[0].cycles, 128.0);

    c = banksOf(4, 1024);
    hashed = c;
    hashed.mapping = DramMapping::Xor;
    DramBanks oneBank(c, 32.0, 1), everyBank(hashed, 32.0, 1);
    for (std::uint64_t i = 0; i < 8; ++i) {
        oneBank.access(i * 4096, 64, 0);
        everyBank.access(i * 4096, 64, 0);
    }
    EXPECT_DOUBLE_EQ(oneBank.patchTimes()[0].cycles, 180.0);
    EXPECT_EQ(oneBank.patchTimes()[0].limit, DramLimit::Bank);
    EXPECT_DOUBLE_EQ(everyBank.patchTimes()[0].cycles, 36.0);
}

// The open rows carry from one patch to the next; each patch is charged its own accesses only.
// Patch 0 opens bank 0's row (10 + 2 cycles); patch 1's access is a row hit (2); patch 2 opens
// bank 1's row (10 + 2).
TEST(DramBanks, EachPatchIsChargedItsOwnAccessesAndRowsStayOpenAcrossPatches) {
    DramBanks banks(banksOf(4, 1024), 32.0, 3);
    banks.access(0, 64, 0);
    banks.access(64, 64, 1);
    banks.access(1024, 64, 2);
    const std::vector<DramBanks::Time> times = banks.patchTimes();
    EXPECT_DOUBLE_EQ(times[0].cycles, 12.0);
    EXPECT_DOUBLE_EQ(times[1].cycles, 2.0);
    EXPECT_EQ(times[1].limit, DramLimit::Bus);  // a tie between the bus and the bank: the bus
    EXPECT_DOUBLE_EQ(times[2].cycles, 12.0);
    EXPECT_EQ(banks.stats().rowHits, 1u);
}

// Whatever the channels, banks and timings, no patch's DRAM time is below its bytes at the
// whole bus's rate: its busiest channel carries at least its share.
TEST(DramBanks, NoPatchIsFasterThanTheWholeBus) {
    std::mt19937_64 random(7);
    for (const int channels : {1, 2, 8}) {
        DramBankConfig c = banksOf(8, 2048);
        c.channels = channels;
        c.mapping = DramMapping::Xor;
        const std::size_t patches = 50;
        DramBanks banks(c, 32.0, patches);
        std::vector<double> bytes(patches, 0.0);
        for (int i = 0; i < 20000; ++i) {
            const std::size_t patch = random() % patches;
            const std::uint64_t size = 16 + random() % 49;
            banks.access((random() % (1 << 24)) & ~std::uint64_t(63), size, patch);
            bytes[patch] += double(size);
        }
        const std::vector<DramBanks::Time> times = banks.patchTimes();
        for (std::size_t p = 0; p < patches; ++p)
            EXPECT_GE(times[p].cycles * (1 + 1e-12), bytes[p] / 32.0) << channels << " " << p;
    }
}

// The model against one written the plain way on random streams: every bank's open row in a
// map keyed by (channel, bank), the address split by shifts, each patch's cycles per bank and
// per channel summed in maps.
TEST(DramBanks, EqualsABruteForceModelOnRandomStreams) {
    struct Shape {
        int channels, banks;
        std::uint32_t channelBytes, rowBytes;
        DramMapping mapping;
    };
    const DramMapping linear = DramMapping::Linear, xorMapping = DramMapping::Xor;
    for (const Shape& shape :
         {Shape{1, 1, 64, 64, linear}, Shape{1, 4, 256, 1024, linear},
          Shape{4, 16, 256, 4096, linear}, Shape{8, 8, 1024, 2048, linear},
          Shape{3, 5, 128, 512, linear}, Shape{8, 8, 256, 4096, xorMapping},
          Shape{2, 16, 64, 1024, xorMapping}, Shape{1, 2, 256, 512, xorMapping}}) {
        DramBankConfig c = banksOf(shape.banks, shape.rowBytes);
        c.channels = shape.channels;
        c.channelBytes = shape.channelBytes;
        c.mapping = shape.mapping;
        const std::size_t patches = 7;
        const double bytesPerClock = 16.0;
        DramBanks banks(c, bytesPerClock, patches);
        using Bank = std::pair<std::uint64_t, std::uint64_t>;  // (channel, bank)
        std::map<Bank, std::uint64_t> openRow;
        std::map<std::pair<std::size_t, Bank>, double> bankBusy;
        std::map<std::pair<std::size_t, std::uint64_t>, double> channelBus, channelActivations;
        std::uint64_t hits = 0, activations = 0;
        std::mt19937_64 random(std::uint64_t(shape.channels * 1000 + shape.banks));
        const int runShift = std::countr_zero(shape.channelBytes);
        const int rowShift = std::countr_zero(shape.rowBytes);
        for (int i = 0; i < 100000; ++i) {
            // Mostly within 64 KiB (rows reused), sometimes anywhere in 64 MiB.
            const std::uint64_t address =
                (random() % 4 ? random() % (64 * 1024) : random() % (1 << 26)) & ~std::uint64_t(63);
            const std::uint64_t bytes = 16 + random() % 49;
            const std::size_t patch = random() % patches;
            banks.access(address, bytes, patch);
            const std::uint64_t run = address >> runShift;
            const std::uint64_t channel = run % std::uint64_t(shape.channels);
            const std::uint64_t inChannel = ((run / std::uint64_t(shape.channels)) << runShift) |
                                            (address & (std::uint64_t(shape.channelBytes) - 1));
            const std::uint64_t row = (inChannel >> rowShift) / std::uint64_t(shape.banks);
            Bank bank{channel, (inChannel >> rowShift) % std::uint64_t(shape.banks)};
            if (shape.mapping == DramMapping::Xor) {
                // Every log2(channels)-bit group of the run, XORed; the bank with the row's bits.
                const int width = std::countr_zero(unsigned(shape.channels));
                bank.first = 0;
                for (int from = 0; width > 0 && from < 64; from += width)
                    bank.first ^= (run >> from) & std::uint64_t(shape.channels - 1);
                bank.second ^= row & std::uint64_t(shape.banks - 1);
            }
            double& busy = bankBusy[{patch, bank}];
            const auto open = openRow.find(bank);
            if (open != openRow.end() && open->second == row) {
                ++hits;
            } else {
                busy += (open != openRow.end() ? c.prechargeCycles : 0.0) + c.activateCycles;
                openRow[bank] = row;
                ++activations;
                channelActivations[{patch, bank.first}] += 1;
            }
            const double transfer = double(bytes) / (bytesPerClock / double(shape.channels));
            busy += transfer;
            channelBus[{patch, bank.first}] += transfer;
        }
        // Each patch: the longest of its own loads.
        const std::vector<DramBanks::Time> times = banks.patchTimes();
        for (std::size_t p = 0; p < patches; ++p) {
            double longest = 0;
            for (const auto& [key, cycles] : bankBusy)
                if (key.first == p) longest = std::max(longest, cycles);
            for (const auto& [key, cycles] : channelBus)
                if (key.first == p) longest = std::max(longest, cycles);
            for (const auto& [key, count] : channelActivations)
                if (key.first == p) longest = std::max(longest, count * c.activateToActivateCycles);
            EXPECT_NEAR(times[p].cycles, longest, 1e-9 * longest);
        }
        EXPECT_EQ(banks.stats().rowHits, hits);
        EXPECT_EQ(banks.stats().activations, activations);
        EXPECT_EQ(banks.stats().transfers, 100000u);
    }
}

}  // namespace
}  // namespace patchsim
