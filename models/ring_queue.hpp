// The event mode's record of a Triangle FIFO: the pop cycles of the triangles
// in it, oldest first. A ring over one growing array (a power of two), so
// that the front, a push and a pop each touch one cache line and nothing is
// allocated once it has grown to the FIFO's depth.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace raplas::model {

class RingQueue {
public:
    bool empty() const { return count_ == 0; }
    std::size_t size() const { return count_; }
    std::uint64_t front() const { return buf_[head_]; }
    // The i-th oldest entry (i < size()).
    std::uint64_t& operator[](std::size_t i) { return buf_[(head_ + i) & mask_]; }
    std::uint64_t operator[](std::size_t i) const { return buf_[(head_ + i) & mask_]; }
    void push_back(std::uint64_t v) {
        if (count_ && buf_[(head_ + count_ - 1) & mask_] == v) ++ties_;
        if (count_ == buf_.size()) grow();
        buf_[(head_ + count_) & mask_] = v;
        ++count_;
    }
    void pop_front() {
        if (count_ > 1 && buf_[head_] == buf_[(head_ + 1) & mask_]) --ties_;
        head_ = (head_ + 1) & mask_;
        --count_;
    }
    // How many entries equal the one before them (triangles popped in the
    // same cycle as the one ahead). operator[]'s writes must keep it: the
    // event mode only moves every entry by the same amount.
    std::uint32_t ties() const { return ties_; }

private:
    void grow() {
        std::vector<std::uint64_t> b(buf_.empty() ? 16 : 2 * buf_.size());
        for (std::size_t i = 0; i < count_; ++i) b[i] = (*this)[i];
        buf_.swap(b);
        head_ = 0;
        mask_ = static_cast<std::uint32_t>(buf_.size() - 1);
    }
    std::vector<std::uint64_t> buf_;
    // (32 bits: with the Fetcher's queue, an ICC's record fills one cache line)
    std::uint32_t head_ = 0, count_ = 0, mask_ = 0, ties_ = 0;
};

}  // namespace raplas::model
