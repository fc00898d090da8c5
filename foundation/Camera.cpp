#include "foundation/Camera.h"

#include <cmath>

namespace fp {

Mat4d inverse(const Mat4d& a) {
    // Laplace expansion with 2×2 sub-determinants; exact enough in double for camera matrices.
    const auto& m = a.m;
    double s0 = m[0] * m[5] - m[4] * m[1], s1 = m[0] * m[6] - m[4] * m[2];
    double s2 = m[0] * m[7] - m[4] * m[3], s3 = m[1] * m[6] - m[5] * m[2];
    double s4 = m[1] * m[7] - m[5] * m[3], s5 = m[2] * m[7] - m[6] * m[3];
    double c5 = m[10] * m[15] - m[14] * m[11], c4 = m[9] * m[15] - m[13] * m[11];
    double c3 = m[9] * m[14] - m[13] * m[10], c2 = m[8] * m[15] - m[12] * m[11];
    double c1 = m[8] * m[14] - m[12] * m[10], c0 = m[8] * m[13] - m[12] * m[9];
    double det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    if (det == 0.0) return Mat4d::zero();
    double inv = 1.0 / det;
    Mat4d r;
    auto& o = r.m;
    o[0] = (m[5] * c5 - m[6] * c4 + m[7] * c3) * inv;
    o[1] = (-m[1] * c5 + m[2] * c4 - m[3] * c3) * inv;
    o[2] = (m[13] * s5 - m[14] * s4 + m[15] * s3) * inv;
    o[3] = (-m[9] * s5 + m[10] * s4 - m[11] * s3) * inv;
    o[4] = (-m[4] * c5 + m[6] * c2 - m[7] * c1) * inv;
    o[5] = (m[0] * c5 - m[2] * c2 + m[3] * c1) * inv;
    o[6] = (-m[12] * s5 + m[14] * s2 - m[15] * s1) * inv;
    o[7] = (m[8] * s5 - m[10] * s2 + m[11] * s1) * inv;
    o[8] = (m[4] * c4 - m[5] * c2 + m[7] * c0) * inv;
    o[9] = (-m[0] * c4 + m[1] * c2 - m[3] * c0) * inv;
    o[10] = (m[12] * s4 - m[13] * s2 + m[15] * s0) * inv;
    o[11] = (-m[8] * s4 + m[9] * s2 - m[11] * s0) * inv;
    o[12] = (-m[4] * c3 + m[5] * c1 - m[6] * c0) * inv;
    o[13] = (m[0] * c3 - m[1] * c1 + m[2] * c0) * inv;
    o[14] = (-m[12] * s3 + m[13] * s1 - m[14] * s0) * inv;
    o[15] = (m[8] * s3 - m[9] * s1 + m[10] * s0) * inv;
    return r;
}

CameraView CameraView::lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& worldUp,
                              double fovYDegrees, int width, int height, double nearPlane) {
    CameraView c;
    c.position = eye;
    c.forward = normalize(target - eye);
    // Scene files (glTF, OBJ, the Cornell data) use right-handed world axes, so right =
    // forward × up keeps the image unmirrored; view space itself stays x right, y up, z forward.
    c.right = normalize(cross(c.forward, worldUp));
    c.up = cross(c.right, c.forward);
    c.fy = 1.0 / std::tan(fovYDegrees * kPi / 360.0);
    c.fx = c.fy * double(height) / double(width);
    c.width = width;
    c.height = height;
    c.nearPlane = nearPlane;
    return c;
}

CameraView CameraView::fromMatrices(const Mat4d& view, const Mat4d& proj, int width, int height) {
    CameraView c;
    c.right = {view(0, 0), view(0, 1), view(0, 2)};
    c.up = {view(1, 0), view(1, 1), view(1, 2)};
    c.forward = {view(2, 0), view(2, 1), view(2, 2)};
    Vec3d t{view(0, 3), view(1, 3), view(2, 3)};
    // eye = −Rᵀ·t
    c.position = -(c.right * t.x + c.up * t.y + c.forward * t.z);
    c.fx = proj(0, 0);
    c.cx = proj(0, 2);
    c.fy = proj(1, 1);
    c.cy = proj(1, 2);
    const double p22 = proj(2, 2), p23 = proj(2, 3);
    // device = p22 + p23/z: near where device = 1, far where device = 0.
    c.nearPlane = p23 / (1.0 - p22);
    c.farPlane = p22 == 0.0 ? std::numeric_limits<double>::infinity() : -p23 / p22;
    c.width = width;
    c.height = height;
    return c;
}

Mat4d CameraView::viewMatrix() const {
    Mat4d v;
    const Vec3d rows[3] = {right, up, forward};
    for (int r = 0; r < 3; ++r) {
        v(r, 0) = rows[r].x;
        v(r, 1) = rows[r].y;
        v(r, 2) = rows[r].z;
        v(r, 3) = -dot(rows[r], position);
    }
    return v;
}

Mat4d CameraView::projectionMatrix() const {
    Mat4d p = Mat4d::zero();
    p(0, 0) = fx;
    p(0, 2) = cx;
    p(1, 1) = fy;
    p(1, 2) = cy;
    // algorithms §1.2: infinite reversed Z has M[2][2] = 0, M[3][2] = NearZ
    p(2, 2) = projectionZScale();
    p(2, 3) = projectionZOffset();
    p(3, 2) = 1.0;
    return p;
}

}  // namespace fp
