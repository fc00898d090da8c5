#pragma once
// Counter-based per-pixel random numbers (docs/design.md, Numerics and determinism): the stream of a pixel depends only on
// (frame, x, y, pass seed), never on which thread ran it or how frames were chunked.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <cstdint>

namespace fp {

/// PCG's state step and output permutation (Jarzynski & Olano 2020, "pcg"); U: uint32_t, or
/// unsigned lanes (foundation/LaneFloat.h's LaneUInt: the same operations lane by lane, each lane
/// shifted by its own amount).
template <class U>
FP_HD constexpr U pcgStep(U state) { return state * 747796405u + 2891336453u; }
template <class U>
FP_HD constexpr U pcgPermute(U state) {
    const U word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
/// One step's permutation, used as a 32-bit integer hash.
template <class U>
FP_HD constexpr U pcgHashOf(U v) { return pcgPermute(pcgStep(v)); }
constexpr uint32_t pcgHash(uint32_t v) { return pcgHashOf(v); }

/// Rng::nextFloat of the stream whose state is `state`, which it advances: uniform in [0, 1), the
/// top 24 bits over 2²⁴, so the result is exact. T: float, or float lanes (their UIntOf states).
template <class T>
FP_HD constexpr T nextFloatOf(UIntOf<T>& state) {
    state = pcgStep(state);
    return toFloat(pcgPermute(state) >> 8u) * (1.0f / 16777216.0f);
}

class Rng {
public:
    /// A placeholder, to be assigned a seeded stream before use.
    Rng() = default;
    /// `frame` is the absolute frame number so a chunked farm run equals a sequential one.
    constexpr Rng(int64_t frame, int x, int y, uint32_t seed)
        : Rng(fromKey(frameKey(frame, seed), x, y)) {}

    /// The part of a pixel's seed that all pixels of a frame share (for code that seeds many).
    static constexpr uint32_t frameKey(int64_t frame, uint32_t seed) {
        return pcgHash(uint32_t(frame) ^ pcgHash(seed ^ uint32_t(uint64_t(frame) >> 32)));
    }
    /// Rng(frame, x, y, seed) from its frame key.
    static constexpr Rng fromKey(uint32_t key, int x, int y) {
        return resume(pcgHash(uint32_t(x) ^ pcgHash(uint32_t(y) ^ key)));
    }
    /// A stream continued from a state() saved earlier.
    static constexpr Rng resume(uint32_t state) {
        Rng r;
        r.mState = state;
        return r;
    }
    constexpr uint32_t state() const { return mState; }

    constexpr uint32_t nextUint() {
        mState = pcgStep(mState);
        return pcgPermute(mState);
    }
    /// Uniform in [0, 1): the top 24 bits, so the result is exactly representable.
    constexpr float nextFloat() { return nextFloatOf<float>(mState); }

private:
    uint32_t mState = 0;
};

}  // namespace fp
