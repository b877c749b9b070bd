// KeepAliveList on its own (rhi/backend-api/janus/rhi/keep_alive.h): what a command list holds for
// its recordings, and when it trusts an object's mark. The per-backend tests (bindings_test.cpp,
// FirstRecordingKeepsDroppedHandlesAlive and the following) check the same through real lists.
#include <janus/rhi/keep_alive.h>

#include <gtest/gtest.h>

#include <memory>

namespace janus::rhi {
namespace {

struct Object {
    KeepMark keepMark;
};

std::shared_ptr<Object> makeObject() { return std::make_shared<Object>(); }

// A recording that uses nothing: the list lets go of everything it held.
void recordNothing(KeepAliveList& list) {
    list.beginRecording();
    list.releaseUnused();
}

TEST(KeepAliveList, AnObjectIsHeldUntilARecordingDoesNotUseIt) {
    KeepAliveList list;
    auto object = makeObject();
    const std::weak_ptr<Object> watch = object;

    list.beginRecording();
    EXPECT_FALSE(list.keepIfHeld(object->keepMark)) << "a new list holds nothing";
    list.keep(object, object->keepMark);
    EXPECT_TRUE(list.keepIfHeld(object->keepMark)) << "held by this recording";
    list.releaseUnused();
    object.reset();
    EXPECT_FALSE(watch.expired()) << "dropped by the user, still held by the list";

    list.beginRecording();
    auto kept = watch.lock();
    EXPECT_TRUE(list.keepIfHeld(kept->keepMark)) << "held since an earlier recording";
    kept.reset();
    list.releaseUnused();
    EXPECT_FALSE(watch.expired()) << "used by the last recording";

    recordNothing(list);
    EXPECT_TRUE(watch.expired()) << "a recording without it lets it go";
}

// An object released from a list keeps the slot its mark names, and the list's vector keeps the
// released entry's bytes past its end (its capacity). Only the bounds check tells the list that
// the slot is no longer its own: without it, the list would take the stale entry for a hold and
// bind an object it no longer keeps alive.
TEST(KeepAliveList, ASlotPastTheEntriesIsNotAHold) {
    KeepAliveList list;
    auto first = makeObject();
    auto second = makeObject();   // slot 1
    const std::weak_ptr<Object> watchSecond = second;

    list.beginRecording();
    list.keep(first, first->keepMark);
    list.keep(second, second->keepMark);
    list.releaseUnused();

    list.beginRecording();   // uses only the first: the second's entry goes
    EXPECT_TRUE(list.keepIfHeld(first->keepMark));
    list.releaseUnused();
    EXPECT_EQ(second->keepMark.slot.load(), 1u) << "the mark still names the released slot";

    list.beginRecording();
    EXPECT_FALSE(list.keepIfHeld(second->keepMark)) << "slot 1 is past the list's one entry";
    list.keep(second, second->keepMark);
    list.releaseUnused();
    second.reset();
    EXPECT_FALSE(watchSecond.expired()) << "held again once kept again";
}

// Two lists holding one object: the mark names whichever list held it last, and each list trusts
// the slot only when its own entry there is this object's.
TEST(KeepAliveList, ListsSharingAnObjectEachHoldIt) {
    KeepAliveList a, b;
    auto shared = makeObject();
    auto onlyB = makeObject();
    const std::weak_ptr<Object> watch = shared;

    a.beginRecording();
    a.keep(shared, shared->keepMark);   // a's slot 0
    a.releaseUnused();

    b.beginRecording();
    b.keep(onlyB, onlyB->keepMark);     // b's slot 0
    b.keep(shared, shared->keepMark);   // b's slot 1: the mark now names it
    b.releaseUnused();

    a.beginRecording();
    EXPECT_FALSE(a.keepIfHeld(shared->keepMark)) << "the mark names b's slot 1, past a's one entry";
    a.keep(shared, shared->keepMark);   // held twice until releaseUnused drops the unused one
    a.releaseUnused();
    EXPECT_EQ(shared->keepMark.slot.load(), 0u) << "a's entry for it, moved down to slot 0";

    b.beginRecording();
    EXPECT_TRUE(b.keepIfHeld(onlyB->keepMark));
    EXPECT_FALSE(b.keepIfHeld(shared->keepMark)) << "the mark names slot 0, where b holds another object";
    b.keep(shared, shared->keepMark);
    b.releaseUnused();

    shared.reset();
    EXPECT_FALSE(watch.expired()) << "both lists' last recordings used it";
    recordNothing(a);
    EXPECT_FALSE(watch.expired()) << "b still holds it";
    recordNothing(b);
    EXPECT_TRUE(watch.expired()) << "neither list holds it";
}

}  // namespace
}  // namespace janus::rhi
