#include "pipeline/timing/dram_banks.h"

#include <algorithm>
#include <bit>

namespace patchsim {

DramBanks::DramBanks(const DramBankConfig& config, double bytesPerClock, std::size_t patches)
    : config_(config),
      channelCyclesPerByte_(double(config.channels) / bytesPerClock),
      openRow_(std::size_t(config.totalBanks()), kNoRow),
      bankBusy_(patches * std::size_t(config.totalBanks()), 0.0),
      channelBus_(patches * std::size_t(config.channels), 0.0),
      channelActivations_(patches * std::size_t(config.channels), 0) {}

namespace {

// `value`'s bits folded into `width` bits: every group of `width` XORed together.
std::uint64_t foldBits(std::uint64_t value, int width) {
    std::uint64_t folded = 0;
    for (; value != 0; value >>= width) folded ^= value & ((std::uint64_t(1) << width) - 1);
    return folded;
}

}  // namespace

const char* dramMappingName(DramMapping mapping) {
    return mapping == DramMapping::Xor ? "xor" : "linear";
}

void DramBanks::access(std::uint64_t address, std::uint64_t bytes, std::size_t patch) {
    const auto channels = std::uint64_t(config_.channels), banks = std::uint64_t(config_.banks);
    const auto runBytes = std::uint64_t(config_.channelBytes);
    const std::uint64_t run = address / runBytes;
    const std::uint64_t inChannel = run / channels * runBytes + address % runBytes;
    const std::uint64_t chunk = inChannel / config_.rowBytes;
    const std::uint64_t row = chunk / banks;
    std::uint64_t channel = run % channels, bankInChannel = chunk % banks;
    if (config_.mapping == DramMapping::Xor) {
        channel = channels > 1 ? foldBits(run, std::countr_zero(channels)) : 0;
        bankInChannel ^= row % banks;
    }
    const std::uint64_t bank = channel * banks + bankInChannel;
    const std::size_t channelSlot = patch * std::size_t(config_.channels) + std::size_t(channel);
    double& busy = bankBusy_[patch * std::size_t(config_.totalBanks()) + std::size_t(bank)];
    ++stats_.transfers;
    if (openRow_[bank] == row) {
        ++stats_.rowHits;
    } else {
        if (openRow_[bank] != kNoRow) busy += config_.prechargeCycles;
        busy += config_.activateCycles;
        openRow_[bank] = row;
        ++stats_.activations;
        ++channelActivations_[channelSlot];
    }
    const double transfer = double(bytes) * channelCyclesPerByte_;
    busy += transfer;
    channelBus_[channelSlot] += transfer;
}

const char* dramLimitName(DramLimit limit) {
    constexpr const char* kNames[] = {"bus", "bank", "activations"};
    return kNames[std::size_t(limit)];
}

std::vector<DramBanks::Time> DramBanks::patchTimes() const {
    const std::size_t patches = channelBus_.size() / std::size_t(config_.channels);
    const auto banks = std::size_t(config_.banks), channels = std::size_t(config_.channels);
    std::vector<Time> times(patches);
    for (std::size_t p = 0; p < patches; ++p) {
        Time& longest = times[p];
        // A tie goes to the bus, then to the banks: the cheaper explanation first.
        const auto consider = [&](double load, DramLimit limit) {
            if (load > longest.cycles) longest = {load, limit};
        };
        for (std::size_t c = 0; c < channels; ++c)
            consider(channelBus_[p * channels + c], DramLimit::Bus);
        for (std::size_t b = 0; b < banks * channels; ++b)
            consider(bankBusy_[p * banks * channels + b], DramLimit::Bank);
        for (std::size_t c = 0; c < channels; ++c)
            consider(
                double(channelActivations_[p * channels + c]) * config_.activateToActivateCycles,
                DramLimit::Activations);
    }
    return times;
}

}  // namespace patchsim
