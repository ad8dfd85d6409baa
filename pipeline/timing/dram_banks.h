#pragma once
// DRAM's banks and rows: what a line costs beyond its bytes on the bus, from where it lies.
// Optional in a hardware file (memory.dram.banks); without it DRAM is an ideal bus that moves
// every byte at its peak rate whatever the address order.
//
// Representation
// --------------
// DRAM is `channels` channels, each with its own share of the data bus (bytes_per_clock /
// channels) and `banks` banks. Each bank is an array of rows of `row_bytes`; a bank reads or
// writes only the row open in its row buffer. Addresses are interleaved over the channels in
// runs of `channel_bytes`: address a lies in run r = a / channel_bytes, at channel address
// c = (r / channels) x channel_bytes + a mod channel_bytes. Within a channel, c lies in chunk
// k = c / row_bytes, row k / banks. Which channel and bank, by the `mapping`:
// - `linear`: channel r mod channels, bank k mod banks. A sequential stream fills one row of
//   each bank in turn, but a stride of channels x channel_bytes (or of a whole row per bank)
//   lands on one channel (or bank) every time: the camping that address hashing avoids.
// - `xor`: the same bits XORed with the higher ones (channels and banks powers of two): the
//   channel is r's bits folded in groups of log2(channels), all XORed together; the bank is
//   (k mod banks) XOR (row mod banks), permutation-based interleaving (Zhang, Zhu and Zhang,
//   MICRO 2000). Both are one-to-one, so no two addresses share a place.
// The policy is open page (ATTILA's memory controller v2 default): a bank keeps its last row
// open; an access to the open row is a row hit and costs only its transfer; any other is an
// activation: a precharge of the open row (t_rp; none before the bank's first activation) and
// then an activate (t_rcd).
//
// The channels and banks are occupancy servers, as the rest of the memory system is
// (timing_model.h), whose server takes one patch at a time and is busy for the longest of its
// parts. Over one patch's DRAM transfers, each channel's bus is busy for its bytes at its share of
// the bandwidth; each bank for its activations' t_rp + t_rcd plus its own transfers; and each
// channel's activations follow one another at least t_rrd apart (the activate-to-activate delay
// between a channel's banks). The patch's DRAM time is the longest of these (a tie goes to the
// bus): never less than its bytes at the whole bus's rate, since its busiest channel carries at
// least its share. Banks overlap each other's activations, so a stream that keeps many banks
// busy runs at the bus's rate, and one that reopens rows of few banks runs at the banks'; traffic
// that falls on few channels runs at their share of the bus. A patch's few lines spread unevenly
// over the channels cost it more than the whole bus's rate, as no later patch's traffic is
// overlapped with its own. A transfer lies at its line's uncompressed address (a compressed depth
// line moves fewer bytes, but from the row its block lies in). The open rows carry across
// patches in the replay's order, the modelled hardware's; all times are in core cycles.
//
// Not modelled: the column and write timings (CAS, WL, tWR), read-to-write turnarounds (tWTR,
// tRTW), a row's least open time (tRAS, so tRC = tRAS + tRP between two activations of one bank
// is taken as t_rcd + t_rp plus the transfers), refresh, the four-activation window, and a
// scheduler that reorders requests (each is served in the replay's order).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace patchsim {

enum class DramMapping : std::uint8_t { Linear, Xor };
const char* dramMappingName(DramMapping mapping);  // "linear", "xor"

struct DramBankConfig {
    DramMapping mapping = DramMapping::Linear;
    int channels = 1;
    int banks = 0;  // per channel; 0: an ideal bus, no banks modelled
    std::uint32_t channelBytes = 256;
    std::uint32_t rowBytes = 4096;
    double activateCycles = 0;            // t_rcd: activate to the first access of the row
    double prechargeCycles = 0;           // t_rp: precharge of the open row before another's
    double activateToActivateCycles = 0;  // t_rrd: between activations in one channel
    bool modelled() const { return banks > 0; }
    int totalBanks() const { return channels * banks; }
};

// What limits a patch's DRAM time: a channel's bus, one of its banks, or its activations' t_rrd.
enum class DramLimit : std::uint8_t { Bus, Bank, Activations };
inline constexpr int kDramLimits = 3;
const char* dramLimitName(DramLimit limit);  // "bus", "bank", "activations"

struct DramBankStats {
    std::uint64_t transfers = 0, rowHits = 0, activations = 0;
    // The patches' DRAM cycles, each patch's under the kind of load that set them.
    std::array<double, kDramLimits> cyclesLimitedBy{};
    double rowHitRate() const { return transfers ? double(rowHits) / double(transfers) : 0.0; }
};

class DramBanks {
  public:
    DramBanks(const DramBankConfig& config, double bytesPerClock, std::size_t patches);

    // One transfer of `bytes` bytes at `address`, charged to `patch`.
    void access(std::uint64_t address, std::uint64_t bytes, std::size_t patch);

    // Each patch's DRAM time: the longest of its channels' bus, banks' and activations' loads,
    // and which kind of load that is.
    struct Time {
        double cycles = 0;
        DramLimit limit = DramLimit::Bus;
    };
    std::vector<Time> patchTimes() const;
    const DramBankStats& stats() const { return stats_; }
    bool modelled() const { return config_.modelled(); }

    static constexpr std::uint64_t kNoRow = ~std::uint64_t(0);

  private:
    DramBankConfig config_;
    double channelCyclesPerByte_;         // at a channel's share of the bus
    std::vector<std::uint64_t> openRow_;  // per bank, channel after channel
    // Per patch: each bank's busy cycles, then per channel its bus cycles and activations.
    std::vector<double> bankBusy_, channelBus_;
    std::vector<std::uint32_t> channelActivations_;
    DramBankStats stats_;
};

}  // namespace patchsim
