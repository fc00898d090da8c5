#pragma once
// Plain views of one image plane — pointer, size, row stride — that per-pixel code takes by value.
// The CPU passes make them from a Plane, the CUDA kernels from a DeviceImage, so one FP_HD
// function reads and writes pixels the same way on either backend.
#include "foundation/HostDevice.h"
#include "foundation/Image.h"

#include <cstddef>

namespace fp {

/// Offset of pixel (x, y) in a plane with `stride` floats per row, in int arithmetic: a plane
/// holds at most limits::kMaxImagePixels (2²⁸) pixels plus row padding, and a GPU computes a
/// 32-bit index in one instruction where a 64-bit one takes five (the HZB march indexes at every
/// sample).
FP_HD inline int planeIndex(int x, int y, std::ptrdiff_t stride) {
    return y * int(stride) + x;
}

/// Read-only view of a plane; `data == nullptr` for an absent one.
struct PlaneView {
    const float* data = nullptr;
    int width = 0, height = 0;
    std::ptrdiff_t stride = 0;  //!< floats between rows

    FP_HD float at(int x, int y) const { return data[planeIndex(x, y, stride)]; }
    /// Coordinates clamped to the plane (the GPU's clamp addressing), as Plane::clampedAt.
    FP_HD float clampedAt(int x, int y) const {
        x = x < 0 ? 0 : (x > width - 1 ? width - 1 : x);
        y = y < 0 ? 0 : (y > height - 1 ? height - 1 : y);
        return at(x, y);
    }
};

/// p.at(x, y): the scalar form of a read that LaneFloat.h makes at each lane's own (x, y).
FP_HD inline float gatherAt(const PlaneView& p, int x, int y) { return p.at(x, y); }

/// Writable view of a plane; `data == nullptr` for an output nobody asked for.
struct PlaneSpan {
    float* data = nullptr;
    int width = 0, height = 0;
    std::ptrdiff_t stride = 0;

    FP_HD float& at(int x, int y) const { return data[planeIndex(x, y, stride)]; }
    FP_HD explicit operator bool() const { return data != nullptr; }
};

/// Views of a host Plane, or (unchanged) of a device plane, so templates serve both backends.
FP_HD inline PlaneView viewOf(const PlaneView& v) {
    return v;
}
FP_HD inline PlaneSpan spanOf(const PlaneSpan& v) {
    return v;
}
FP_HD inline PlaneView viewOf(const PlaneSpan& v) {
    return {v.data, v.width, v.height, v.stride};
}
inline PlaneView viewOf(const Plane& p) {
    return {p.empty() ? nullptr : p.row(0), p.width(), p.height(), p.stride()};
}
inline PlaneSpan spanOf(Plane& p) {
    return {p.empty() ? nullptr : p.row(0), p.width(), p.height(), p.stride()};
}

}  // namespace fp
