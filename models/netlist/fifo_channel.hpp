// The netlist's FIFOs are channels: a writer pushes through a port on
// FifoWriteIf, its reader pops through a port on FifoReadIf, and both see
// the contents at the start of the cycle: a push or pop made at a clock edge
// takes effect in the update phase that follows (pops first, then the push),
// as a register does. "Full" is therefore judged on the occupancy at the
// start of the cycle (docs/MODEL.md §3). The contents and statistics are the
// ICC's own Fifo / SphereFifo (models/fifo.hpp), which the event engine
// uses directly; the channel adds the timing of a clocked netlist.
#pragma once

#include <systemc>

#include <string>
#include <vector>

#include "../fifo.hpp"
#include "signals.hpp"

namespace raplas::model::netlist {

// The channel a port is bound to.
template <class IF, int N, sc_core::sc_port_policy P>
IF& bound(sc_core::sc_port<IF, N, P>& port) {
    return *port.operator->();
}
template <class IF, int N, sc_core::sc_port_policy P>
const IF& bound(const sc_core::sc_port<IF, N, P>& port) {
    return *port.operator->();
}

// What every side may look at: the contents at the start of the cycle, and
// events for a change of them (default_event), of the entry at the front or
// whether there is one (front_event), and of the full flag (full_event).
template <class T>
struct FifoStatusIf : virtual sc_core::sc_interface {
    virtual bool empty() const = 0;
    virtual bool full() const = 0;
    virtual std::uint32_t size() const = 0;
    virtual T at(std::uint32_t i) const = 0;  // the entry i places behind the front
    T front() const { return at(0); }
    virtual const sc_core::sc_event& default_event() const = 0;
    virtual const sc_core::sc_event& front_event() const = 0;
    virtual const sc_core::sc_event& full_event() const = 0;
};
// Sensitivity to one of those events of the FIFO a port is bound to
// (`sensitive << finder`; a member of the module, as it must outlive elaboration).
template <class T>
using FifoEventFinder = sc_core::sc_event_finder_t<FifoStatusIf<T>>;
template <class T, class Port>
FifoEventFinder<T> front_event_of(const Port& port) {
    return FifoEventFinder<T>(port, &FifoStatusIf<T>::front_event);
}
template <class T, class Port>
FifoEventFinder<T> full_event_of(const Port& port) {
    return FifoEventFinder<T>(port, &FifoStatusIf<T>::full_event);
}
template <class T>
struct FifoWriteIf : virtual FifoStatusIf<T> {
    virtual void push(const T& v) = 0;                 // at most one per cycle
    virtual void note_full(std::uint64_t cycles = 1) = 0;  // a push refused (statistics)
};
template <class T>
struct FifoReadIf : virtual FifoStatusIf<T> {
    virtual void pop(std::uint32_t n = 1) = 0;
};

// Fifo<T> as the channel's store.
template <class T>
struct FifoStore {
    Fifo<T>& fifo;
    T at(std::uint32_t i) const { return fifo.at(i); }
    void push(const T& v) { fifo.push(v); }
};
// SphereFifo as the store of SphereEntry: the FIFO holds a run of
// consecutive sphere indices, and each one's triangle range is kept beside
// it, at its index modulo the depth (no two entries share a slot).
struct SphereStore {
    SphereFifo& fifo;
    std::vector<SphereEntry> range;
    explicit SphereStore(SphereFifo& f) : fifo(f), range(f.depth()) {}
    SphereEntry at(std::uint32_t i) const { return range[fifo.at(i) % fifo.depth()]; }
    void push(const SphereEntry& e) {
        range[e.sphere % fifo.depth()] = e;
        fifo.push(e.sphere);
    }
};

template <class T, class Store>
class FifoChannel : public sc_core::sc_prim_channel, public FifoWriteIf<T>, public FifoReadIf<T> {
public:
    template <class F>
    FifoChannel(const char* name, F& fifo) : sc_core::sc_prim_channel(name), store_(Store{fifo}) {
        sample();
    }

    bool empty() const override { return store_.fifo.empty(); }
    bool full() const override { return store_.fifo.full(); }
    std::uint32_t size() const override { return store_.fifo.size(); }
    T at(std::uint32_t i) const override { return store_.at(i); }
    const sc_core::sc_event& default_event() const override { return changed_; }
    const sc_core::sc_event& front_event() const override { return front_changed_; }
    const sc_core::sc_event& full_event() const override { return full_changed_; }
    void push(const T& v) override {
        pushed_ = v;
        has_push_ = true;
        request_update();
    }
    void note_full(std::uint64_t cycles) override { store_.fifo.note_full(cycles); }
    void pop(std::uint32_t n) override {
        pops_ += n;
        request_update();
    }
    // The contents were changed from outside (the ICC cleared it for a new
    // pass): tells the readers, and the waveform.
    void refresh() {
        sample();
        changed_.notify(sc_core::SC_ZERO_TIME);
        front_changed_.notify(sc_core::SC_ZERO_TIME);
        full_changed_.notify(sc_core::SC_ZERO_TIME);
    }
    // Its occupancy and full flag in the waveform (name.size, name.full).
    void trace(sc_core::sc_trace_file* tf) const override {
        sc_core::sc_trace(tf, size_, std::string(name()) + ".size");
        sc_core::sc_trace(tf, full_, std::string(name()) + ".full");
    }

protected:
    void update() override {
        const bool was_empty = store_.fifo.empty(), was_full = store_.fifo.full();
        const bool front_moves = pops_ || (was_empty && has_push_);
        for (; pops_; --pops_) store_.fifo.pop();
        if (has_push_) store_.push(pushed_);
        has_push_ = false;
        sample();
        changed_.notify(sc_core::SC_ZERO_TIME);
        if (front_moves) front_changed_.notify(sc_core::SC_ZERO_TIME);
        if (full_ != was_full) full_changed_.notify(sc_core::SC_ZERO_TIME);
    }

private:
    void sample() {
        size_ = store_.fifo.size();
        full_ = store_.fifo.full();
    }

    Store store_;
    T pushed_{};
    bool has_push_ = false;
    std::uint32_t pops_ = 0;
    std::uint32_t size_ = 0;
    bool full_ = false;
    sc_core::sc_event changed_, front_changed_, full_changed_;
};

template <class T>
using FifoChannelOf = FifoChannel<T, FifoStore<T>>;
using SphereFifoChannel = FifoChannel<SphereEntry, SphereStore>;

}  // namespace raplas::model::netlist
