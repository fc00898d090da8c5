#pragma once
// The camera of one frame, in Unreal's conventions (algorithms §1.2–1.3): view space is x right,
// y up, z forward, SceneDepth is view z, device depth is reversed Z (near → 1, sky → 0).
// Positions are handled camera-relative ("translated world"): the camera origin is kept in double
// and per-pixel maths runs on offsets from it, so a camera 10⁷ units from the origin loses nothing.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <limits>
#include <optional>

namespace fp {

/// Device Z = P22 + P23/depth (P22 for an infinite depth) of the projection's `zScale` (P22) and
/// `zOffset` (P23); D: double, or double lanes (LaneFloat.h).
template <class D>
FP_HD D deviceZFromDepthOf(double zScale, double zOffset, D depth) {
    return ifThenElse(isInfOf(depth), D(zScale), zScale + zOffset / depth);
}

class CameraView {
public:
    Vec3d position;                    //!< world position of the eye, scene units
    Vec3d right{1, 0, 0};              //!< world direction of view +x
    Vec3d up{0, 1, 0};                 //!< world direction of view +y
    Vec3d forward{0, 0, 1};            //!< world direction of view +z (depth axis)
    double fx = 1.0, fy = 1.0;         //!< NDC scale: ndc.x = fx·x/z + cx
    double cx = 0.0, cy = 0.0;         //!< off-centre projection, NDC units
    double nearPlane = 10.0;           //!< scene units (Unreal default 10 cm)
    double farPlane = std::numeric_limits<double>::infinity();  //!< ∞: Unreal's infinite far
    int width = 0, height = 0;         //!< pixels

    /// A symmetric camera looking along `forward` with the given vertical field of view.
    static CameraView lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& worldUp,
                             double fovYDegrees, int width, int height, double nearPlane);
    /// Rebuilds a camera from double-precision world→view and view→clip matrices.
    static CameraView fromMatrices(const Mat4d& view, const Mat4d& projection, int width,
                                   int height);

    Mat4d viewMatrix() const;        //!< world → view
    Mat4d projectionMatrix() const;  //!< view → clip, reversed Z
    /// The depth row of projectionMatrix(): device Z = P22 + P23/depth.
    FP_HD double projectionZScale() const {  // P22
        return std::isinf(farPlane) ? 0.0 : -nearPlane / (farPlane - nearPlane);
    }
    FP_HD double projectionZOffset() const {  // P23
        return std::isinf(farPlane) ? nearPlane : nearPlane * farPlane / (farPlane - nearPlane);
    }
    /// Device Z = P22 + P23/depth (algorithms §1.2: NearZ/SceneDepth for the infinite variant).
    FP_HD double deviceZFromDepth(double depth) const {
        return deviceZFromDepthOf(projectionZScale(), projectionZOffset(), depth);
    }
    /// Inverse of deviceZFromDepth; device Z at or below the far value gives +∞ (sky).
    FP_HD double depthFromDeviceZ(double deviceZ) const {
        if (deviceZ <= projectionZScale())
            return std::numeric_limits<double>::infinity();
        return projectionZOffset() / (deviceZ - projectionZScale());
    }

    /// Screen position in [−1, 1]², +y up, of the centre of pixel (px, py) (algorithms §1.3).
    FP_HD double screenX(double px) const { return (px + 0.5) / width * 2.0 - 1.0; }
    FP_HD double screenY(double py) const { return 1.0 - (py + 0.5) / height * 2.0; }
    /// Offset from the eye of the surface at pixel (px, py) and view depth `depth`.
    FP_HD Vec3d translatedFromPixel(double px, double py, double depth) const {
        return translatedFromPixelOf<double>(px, py, depth);
    }
    /// The same for D: double, or double lanes (LaneFloat.h) of pixels of one row, each lane the
    /// same operations in the same order.
    template <class D>
    FP_HD Vec3T<D> translatedFromPixelOf(D px, double py, D depth) const {
        const D vx = (((px + 0.5) / double(width) * 2.0 - 1.0) - cx) * depth / fx;
        const D vy = D(screenY(py) - cy) * depth / fy;
        return Vec3T<D>(right) * vx + Vec3T<D>(up) * vy + Vec3T<D>(forward) * depth;
    }
    /// World position of that surface (double: eye + offset).
    Vec3d worldFromPixel(double px, double py, double depth) const {
        return position + translatedFromPixel(px, py, depth);
    }
    /// Unit direction of the primary ray through pixel (px, py), world axes.
    FP_HD Vec3d rayDirection(double px, double py) const {
        return normalize(translatedFromPixel(px, py, 1.0));
    }

    struct Projection {
        double px, py;  //!< continuous pixel coordinates (pixel centres at +0.5)
        double depth;   //!< view z; ≤ 0 means behind the camera
    };
    /// Projects a point given as an offset from `origin` (pass the same origin the offset was
    /// taken from, e.g. another camera's eye) so nothing large is ever subtracted in float.
    FP_HD Projection projectOffset(const Vec3d& offset, const Vec3d& origin) const {
        // Offset relative to this eye, computed as (origin − eye) + offset: both terms are small
        // when the two eyes are close, whatever their distance from the world origin.
        const Vec3d rel = (origin - position) + offset;
        const double z = dot(rel, forward);
        const double sx = fx * dot(rel, right) / z + cx;
        const double sy = fy * dot(rel, up) / z + cy;
        return {(sx + 1.0) * 0.5 * width, (1.0 - sy) * 0.5 * height, z};
    }
    FP_HD Projection project(const Vec3d& world) const { return projectOffset(world, Vec3d{}); }

    /// tan(half horizontal FOV)/width × depth: the blur radius unit of algorithms §3.2.
    FP_HD double pixelRadiusAtDepth(double depth) const { return depth / (fx * width); }
};

/// Camera of this frame and, when known, of the previous one.
struct FrameCamera {
    CameraView current;
    std::optional<CameraView> previous;
    double sceneUnitsPerMeter = 100.0;  //!< 100 for Unreal (centimetres)
};

}  // namespace fp
