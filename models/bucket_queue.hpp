// The event mode's queue of ICCs keyed by a position in a stream that only
// moves forward (a sphere or a triangle index): each ICC is in it at most
// once, and the smallest key and the ICCs at it are found in amortised
// constant time (one bucket per key, and a bit per bucket that is not empty:
// the bits are scanned once per pass, 64 keys a word). The order of the
// ICCs at one key is unspecified: nothing the model computes depends on it.
#pragma once

#include <cstdint>
#include <vector>

namespace raplas::model {

class BucketQueue {
public:
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);
    // Empty, for keys below `keys` and ICCs below `iccs`.
    void reset(std::size_t keys, std::size_t iccs) {
        if (size_ != 0 || head_.size() != keys + 1) {  // (an empty queue's buckets are all empty already)
            head_.assign(keys + 1, kNone);
            bits_.assign(keys / 64 + 1, 0);
        }
        next_.assign(iccs, kNone);
        min_ = std::uint32_t(keys);
        at_min_ = false;
        size_ = 0;
    }
    bool empty() const { return size_ == 0; }
    void push(std::uint32_t key, std::uint32_t icc) {
        next_[icc] = head_[key];
        head_[key] = icc;
        bits_[key >> 6] |= std::uint64_t(1) << (key & 63);
        if (key <= min_) {
            min_ = key;
            at_min_ = true;
        }
        ++size_;
    }
    // The smallest key (the queue must not be empty). The event loop asks
    // several times a cycle: the answer is kept until the bucket at it is
    // emptied, so that the bucket array (one entry per triangle of the
    // scene) is read again only then.
    std::uint32_t min_key() {
        if (!at_min_) {
            std::size_t w = min_ >> 6;
            std::uint64_t b = bits_[w] & (~std::uint64_t(0) << (min_ & 63));
            while (b == 0) b = bits_[++w];
            min_ = std::uint32_t(w * 64 + std::size_t(__builtin_ctzll(b)));
            at_min_ = true;
        }
        return min_;
    }
    // Takes every ICC at the smallest key out and calls f(icc) for each; f
    // may push (at larger keys).
    template <class F>
    void pop_min(F&& f) {
        const std::uint32_t key = min_key();
        std::uint32_t k = head_[key];
        head_[key] = kNone;
        bits_[key >> 6] &= ~(std::uint64_t(1) << (key & 63));
        at_min_ = false;
        while (k != kNone) {
            const std::uint32_t next = next_[k];
            --size_;
            f(k);
            k = next;
        }
    }

private:
    std::vector<std::uint32_t> head_;  // per key, the first ICC at it; next_ links the others
    std::vector<std::uint32_t> next_;
    std::vector<std::uint64_t> bits_;  // bit key % 64 of word key / 64: head_[key] holds an ICC
    std::uint32_t min_ = 0;  // no key below it is used
    bool at_min_ = false;     // and the bucket at min_ is not empty
    std::size_t size_ = 0;
};

}  // namespace raplas::model
