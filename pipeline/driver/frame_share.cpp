#include "pipeline/driver/frame_share.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace patchsim {

namespace {

class Writer {
  public:
    template <typename T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        putBytes(&value, sizeof(T));
    }
    template <typename T>
    void putArray(const T* values, std::size_t count) {
        static_assert(std::is_trivially_copyable_v<T>);
        putBytes(values, count * sizeof(T));
    }
    std::string take() { return std::move(bytes_); }

  private:
    void putBytes(const void* p, std::size_t n) {
        if (n > 0) bytes_.append(static_cast<const char*>(p), n);
    }
    std::string bytes_;
};

class Reader {
  public:
    explicit Reader(const std::string& bytes) : bytes_(bytes) {}
    template <typename T>
    T get() {
        T value;
        getBytes(&value, sizeof(T));
        return value;
    }
    template <typename T>
    void getArray(T* values, std::size_t count) {
        getBytes(values, count * sizeof(T));
    }
    bool done() const { return at_ == bytes_.size(); }

  private:
    void getBytes(void* p, std::size_t n) {
        if (at_ + n > bytes_.size()) throw std::runtime_error("truncated frame rows");
        if (n == 0) return;  // an empty array may have no storage: memcpy from/to null is undefined
        std::memcpy(p, bytes_.data() + at_, n);
        at_ += n;
    }
    const std::string& bytes_;
    std::size_t at_ = 0;
};

}  // namespace

std::string packFrameRows(const FrameRows& rows, const std::function<bool(int)>& ownsPixelRow,
                          const std::function<bool(int)>& ownsTileRow) {
    const VisibilityBuffer& v = *rows.visibility;
    const std::size_t rowSamples = std::size_t(v.width()) * std::size_t(v.samplesPerPixel());
    Writer out;
    for (int y = 0; y < v.height(); ++y) {
        if (!ownsPixelRow(y)) continue;
        out.put(y);
        const std::size_t first = v.index(0, y, 0);
        out.putArray(v.records().data() + first, rowSamples);
        if (rows.transparent) {
            for (std::size_t s = first; s < first + rowSamples; ++s) {
                const int n = rows.transparent->count(s);
                out.put(n);
                if (n) out.putArray(rows.transparent->layers(s), std::size_t(n));
            }
        }
        if (rows.pixels) {
            for (std::size_t q = 0; q < kPixelQuantities.size(); ++q)
                out.putArray(rows.pixels->values(q).data() + rows.pixels->pixel(0, y),
                             std::size_t(v.width()));
        }
    }
    out.put(-1);  // end of pixel rows
    if (rows.pixels) {
        const TileGrid& g = rows.pixels->grid();
        for (int ty = 0; ty < g.tilesY(); ++ty)
            if (ownsTileRow(ty)) {
                out.put(ty);
                out.putArray(rows.pixels->tileTests().data() + g.index(0, ty),
                             std::size_t(g.tilesX()));
            }
        out.put(-1);
    }
    out.put(rows.ops->size());
    out.putArray(rows.ops->data(), rows.ops->size());
    out.put(rows.counters->raw().size());
    out.putArray(rows.counters->raw().data(), rows.counters->raw().size());
    return out.take();
}

void unpackFrameRows(const std::string& bytes, const FrameRows& rows) {
    VisibilityBuffer& v = *rows.visibility;
    const std::size_t rowSamples = std::size_t(v.width()) * std::size_t(v.samplesPerPixel());
    Reader in(bytes);
    std::vector<LayerFragment> fragments;
    for (int y = in.get<int>(); y >= 0; y = in.get<int>()) {
        const std::size_t first = v.index(0, y, 0);
        in.getArray(&v.at(0, y, 0), rowSamples);
        if (rows.transparent) {
            for (std::size_t s = first; s < first + rowSamples; ++s) {
                fragments.resize(std::size_t(in.get<int>()));
                in.getArray(fragments.data(), fragments.size());
                // The sorted blend does not depend on slot order; any pool will do.
                for (const LayerFragment& f : fragments)
                    rows.transparent->offer(s, y % rows.transparent->pools(), f);
            }
        }
        if (rows.pixels) {
            for (std::size_t q = 0; q < kPixelQuantities.size(); ++q)
                in.getArray(rows.pixels->mutableValues(q).data() + rows.pixels->pixel(0, y),
                            std::size_t(v.width()));
        }
    }
    if (rows.pixels) {
        const TileGrid& g = rows.pixels->grid();
        for (int ty = in.get<int>(); ty >= 0; ty = in.get<int>())
            in.getArray(rows.pixels->mutableTileTests().data() + g.index(0, ty),
                        std::size_t(g.tilesX()));
    }
    std::vector<PatchOps> ops(in.get<std::size_t>());
    in.getArray(ops.data(), ops.size());
    for (std::size_t i = 0; i < ops.size() && i < rows.ops->size(); ++i) (*rows.ops)[i].add(ops[i]);
    std::vector<std::int64_t> counts(in.get<std::size_t>());
    in.getArray(counts.data(), counts.size());
    *rows.counters = CounterValues::fromRaw(std::move(counts));
    if (!in.done()) throw std::runtime_error("frame rows of another size");
}

}  // namespace patchsim
