// The group stream between the front end and the model: the groups it hands
// over are the whole frame's trace, in order, never more than its window at
// once; a failing front end ends the model's waits without a throw, and a
// stopped model releases the waiting workers.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/group_source.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/params.hpp"
#include "raplas/util/worker.hpp"

namespace {

using namespace raplas;

Scene small_builtin() {
    ParamSet p = scene_params();
    p.set("image.width=40");
    p.set("image.height=24");
    p.set("groups.size=8");
    p.set("groups.shadow_size=4");
    p.set("builtin_detail=1");
    return scene_from_params(p, "");
}

// Takes every group of `stream` in order, one at a time, releasing each
// before the next: serialized, each on its own (the hash), and counted.
struct Consumer {
    std::vector<std::string> groups;  // each group in a one-group trace's bytes
    std::string hash;
    std::uint64_t total = 0;
    // ahead: the observers on their own thread (ObserveAhead)
    void run(GroupStream& s, bool pairless, bool ahead = false) {
        const Trace& h = s.header();
        WorkloadTally tally(h, pairless);
        s.observers.push_back(tally.observer());
        std::optional<ObserveAhead> observing;
        if (ahead) observing.emplace(s);
        for (std::size_t i = 0;; ++i) {
            if (s.total_known() && i == s.total_groups()) break;
            if (i >= h.primary_groups) {
                ASSERT_TRUE(s.wait_total());
                if (i == s.total_groups()) break;
            }
            ASSERT_TRUE(s.wait_for(i + 1)) << s.failure_message();
            Trace one = h;
            one.groups = {s.group(i)};
            one.primary_groups = i < h.primary_groups ? 1 : 0;
            groups.push_back(serialize_trace(one));
            s.release(i + 1);
        }
        total = s.total_groups();
        if (observing) observing->stop();
        EXPECT_EQ(tally.groups, total);
        hash = tally.hasher->value();
    }
};

TEST(GroupStream, HandsOverTheWholeFramesGroupsInOrderWithinItsWindow) {
    const Scene scene = small_builtin();
    const auto image = render_frame(scene, FrameOptions{}).rgb;
    for (const bool pairless : {false, true}) {
        FrameOptions fo;
        fo.record = true;
        fo.pairless = pairless;
        fo.threads = 3;
        const Trace whole = make_trace(scene, render_frame(scene, fo), fo.format, pairless);
        ASSERT_GT(whole.groups.size(), whole.primary_groups + 10u);
        for (const std::size_t window : {std::size_t(1), std::size_t(3), std::size_t(7)}) {
          for (const bool ahead : {false, true}) {
            GroupStream stream(window);
            FrameOptions so = fo;
            so.stream = &stream;
            Frame streamed_frame;
            std::thread front([&] { streamed_frame = render_frame(scene, so); });
            Consumer c;
            c.run(stream, pairless, ahead);
            front.join();
            EXPECT_EQ(c.total, whole.groups.size());
            ASSERT_EQ(c.groups.size(), whole.groups.size());
            Trace one = whole;  // (the header; its groups replaced one at a time)
            for (std::size_t i = 0; i < whole.groups.size(); ++i) {
                one.groups = {whole.groups[i]};
                one.primary_groups = i < whole.primary_groups ? 1 : 0;
                ASSERT_EQ(c.groups[i], serialize_trace(one)) << "group " << i << ", window " << window;
            }
            EXPECT_EQ(c.hash, workload_hash(whole, pairless));
            EXPECT_LE(stream.peak_held(), window);
            EXPECT_GE(stream.peak_held(), 1u);
            // The frame keeps no group, and its image is the whole frame's.
            EXPECT_TRUE(streamed_frame.shadow.empty());
            EXPECT_TRUE(streamed_frame.primary_results.empty());
            EXPECT_EQ(streamed_frame.rgb, image);
          }
        }
    }
}

// Observers running ahead see every group once, in issue order, no later than
// its release and no earlier than it is there; they stop with the run, also
// when the front end failed and a group never comes.
TEST(GroupStream, ObserversAheadSeeEachGroupInOrderBeforeItsRelease) {
    GroupStream s(3);
    Trace h;
    h.primary_groups = 6;
    s.set_header(std::move(h));
    std::vector<std::size_t> seen;
    std::atomic<std::size_t> count{0};
    s.observers.push_back([&](std::size_t i, const TraceGroup& g) {
        EXPECT_EQ(g.n, std::uint32_t(i + 1));
        seen.push_back(i);
        ++count;
    });
    {
        ObserveAhead ahead(s);
        for (std::size_t i = 0; i < 3; ++i) {
            s.acquire(i);
            TraceGroup g;
            g.n = std::uint32_t(i + 1);
            s.put(i, std::move(g));
        }
        ASSERT_TRUE(s.wait_for(2));
        s.release(2);  // waits until groups 0 and 1 were observed
        EXPECT_GE(count.load(), 2u);
        EXPECT_LE(count.load(), 3u);  // never a group that is not there (3 is not)
        s.acquire(3);
        TraceGroup g;
        g.n = 4;
        s.put(3, std::move(g));
        ASSERT_TRUE(s.wait_for(4));
        s.release(4);
        EXPECT_EQ(count.load(), 4u);
        try {  // the front end fails: group 4 never comes, and the run ends
            throw InputError("scene.toml: too much");
        } catch (const InputError& e) {
            s.fail(std::current_exception(), e.what());
        }
    }  // (the thread waiting for group 4 stops here)
    EXPECT_EQ(seen, (std::vector<std::size_t>{0, 1, 2, 3}));
    // Without the thread, release() runs the observers itself.
    GroupStream t(2);
    t.set_header(Trace{});
    std::size_t inline_seen = 0;
    t.observers.push_back([&](std::size_t, const TraceGroup&) { ++inline_seen; });
    t.acquire(0);
    t.put(0, TraceGroup{});
    ASSERT_TRUE(t.wait_for(1));
    EXPECT_EQ(inline_seen, 0u);
    t.release(1);
    EXPECT_EQ(inline_seen, 1u);
}

TEST(GroupStream, AFailingFrontEndEndsTheModelsWaitsWithItsMessage) {
    GroupStream s(4);
    Trace h;
    h.primary_groups = 3;
    s.set_header(std::move(h));
    s.acquire(0);
    TraceGroup g;
    g.n = 1;
    s.put(0, std::move(g));
    EXPECT_TRUE(s.wait_for(1));
    EXPECT_FALSE(s.total_known());
    std::thread front([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        try {
            throw InputError("scene.toml: too much");
        } catch (const InputError& e) {
            s.fail(std::current_exception(), std::string("front end: ") + e.what());
        }
    });
    EXPECT_FALSE(s.wait_for(2));  // waits, then learns of the failure
    EXPECT_FALSE(s.wait_total());
    EXPECT_EQ(s.failure_message(), "front end: scene.toml: too much");
    front.join();
    // A worker waiting for room stops too.
    EXPECT_THROW(s.acquire(9), GroupStream::Cancelled);
}

TEST(GroupStream, WorkersWaitForRoomAndACancelReleasesThem) {
    GroupStream s(2);
    s.set_header(Trace{});
    s.acquire(0);
    s.acquire(1);
    std::atomic<int> state{0};
    std::thread worker([&] {
        try {
            s.acquire(2);  // no room until group 0 is released
            state = 1;
            s.acquire(4);  // none until the model cancels
            state = 2;
        } catch (const GroupStream::Cancelled&) {
            state = 3;
        }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(state.load(), 0);
    TraceGroup g;
    g.n = 1;
    s.put(0, std::move(g));
    ASSERT_TRUE(s.wait_for(1));
    s.release(1);
    for (int i = 0; i < 200 && state.load() != 1; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(state.load(), 1);
    s.cancel();
    worker.join();
    EXPECT_EQ(state.load(), 3);
    EXPECT_EQ(s.peak_held(), 2u);  // never more than the window
}

// The thread that loads the model's next pass ahead: each job runs on it,
// one at a time, on the same thread; wait() returns once the job is done and
// rethrows its failure; a job not waited for is still finished before the
// worker goes.
TEST(Worker, RunsEachJobOnItsOneThreadAndRethrowsAtTheWait) {
    std::thread::id started;
    Worker w([&] { started = std::this_thread::get_id(); });
    w.wait();  // (nothing handed over yet)
    std::vector<std::thread::id> ran;
    int sum = 0;
    for (int i = 1; i <= 50; ++i) {
        w.run([&, i] {
            ran.push_back(std::this_thread::get_id());
            sum += i;
        });
        w.wait();
        EXPECT_EQ(sum, i * (i + 1) / 2);
    }
    ASSERT_EQ(ran.size(), 50u);
    EXPECT_NE(ran[0], std::this_thread::get_id());
    EXPECT_EQ(ran[0], started);
    for (const auto& id : ran) EXPECT_EQ(id, ran[0]);

    w.run([] { throw InputError("group 7: bad"); });
    EXPECT_THROW(w.wait(), InputError);
    w.wait();  // (the failure is given once)
    w.run([&] { sum = -1; });
    EXPECT_THROW(w.run([] {}), std::logic_error);  // the last job was not waited for
    w.wait();
    EXPECT_EQ(sum, -1);
}

TEST(Worker, FinishesAJobNotWaitedForBeforeItGoes) {
    std::atomic<bool> done{false};
    {
        Worker w;
        w.run([&] {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            done = true;
        });
    }
    EXPECT_TRUE(done.load());
    {
        Worker idle;  // never handed a job: no thread to end
    }
}

}  // namespace
