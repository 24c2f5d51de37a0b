// Mailboxes: a primitive is tested once per ray, and nothing is skipped after
// the ray counter wraps around.
#include <doctest/doctest.h>

#include "mailbox.h"

using gw::BasicMailbox;

TEST_CASE("a primitive is seen once per ray and again by the next ray") {
    BasicMailbox<uint32_t> mb;
    mb.resize(4);
    mb.next_ray();
    CHECK_FALSE(mb.seen(2));
    CHECK(mb.seen(2));
    CHECK_FALSE(mb.seen(3));
    mb.next_ray();
    CHECK_FALSE(mb.seen(2));
    CHECK(mb.seen(2));
}

TEST_CASE("after the counter wraps around no stale stamp hides a primitive") {
    // 8-bit stamps wrap after 255 rays. Primitive 0 is stamped by ray 1; when
    // the counter comes back to 1 after the wrap, it must not look "seen".
    BasicMailbox<uint8_t> mb;
    mb.resize(3);
    mb.next_ray();               // ray 1
    CHECK_FALSE(mb.seen(0));
    for (int i = 0; i < 254; ++i) mb.next_ray();   // rays 2 .. 255
    CHECK_FALSE(mb.seen(1));     // stamped 255
    mb.next_ray();               // wraps: stamps cleared, ray 1 again
    CHECK_FALSE(mb.seen(0));
    CHECK_FALSE(mb.seen(1));
    CHECK(mb.seen(0));
    for (int ray = 0; ray < 1000; ++ray) {   // many wraps: every ray sees every primitive once
        mb.next_ray();
        for (uint32_t p = 0; p < 3; ++p) CHECK_FALSE(mb.seen(p));
        for (uint32_t p = 0; p < 3; ++p) CHECK(mb.seen(p));
    }
}

TEST_CASE("a mailbox sized to no primitives is disabled") {
    BasicMailbox<uint32_t> mb;
    CHECK_FALSE(mb.enabled());
    mb.resize(1);
    CHECK(mb.enabled());
}
