#include "shading/EnvBRDF.h"

#include "foundation/Sampling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace fp {

namespace {

// The 16-bit unorm texture format Unreal stores the table in (G16R16).
float unorm16(double v) {
    return float(std::round(std::clamp(v, 0.0, 1.0) * 65535.0) / 65535.0);
}

}  // namespace

EnvBRDFTerms integrateEnvBRDF(float NoVf, float roughness, int samples) {
    // In double: the table is generated once, and the test's quadrature compares against it.
    const double NoV = NoVf;
    const double m = double(roughness) * roughness, a2 = m * m;
    const double Vx = std::sqrt(std::max(0.0, 1.0 - NoV * NoV)), Vz = NoV;  // V = (√(1−NoV²), 0, NoV)
    double A = 0, B = 0;
    for (int i = 0; i < samples; ++i) {
        const double e1 = double(i) / samples, e2 = radicalInverse2(uint32_t(i));
        const double phi = 2.0 * kPi * e1;
        const double cosTheta = std::sqrt((1.0 - e2) / (1.0 + (a2 - 1.0) * e2));
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        // H's y is not needed: V has none (only VoH and H's z enter below).
        const double Hx = sinTheta * std::cos(phi), Hz = cosTheta;
        const double VoH = Vx * Hx + Vz * Hz;
        const double Lz = 2.0 * VoH * Hz - Vz;  // L = reflect(−V, H); only its z is needed
        const double NoL = std::clamp(Lz, 0.0, 1.0), NoH = std::clamp(Hz, 0.0, 1.0);
        if (NoL <= 0.0) continue;
        const double vis = 0.5 / (NoL * (NoV * (1.0 - m) + m) + NoV * (NoL * (1.0 - m) + m));
        // The GGX sample's pdf over L is D·NoH/(4·VoH); f·NoL/pdf leaves Vis·NoL·4·VoH/NoH.
        const double w = NoL * vis * 4.0 * std::clamp(VoH, 0.0, 1.0) / NoH;
        const double fc = std::pow(1.0 - std::clamp(VoH, 0.0, 1.0), 5.0);
        A += w * (1.0 - fc);
        B += w * fc;
    }
    return {float(A / samples), float(B / samples)};
}

EnvBRDFTerms envBRDFApprox(float NoV, float roughness) {
    const float r0 = roughness * -1.0f + 1.0f, r1 = roughness * -0.0275f + 0.0425f;
    const float r2 = roughness * -0.572f + 1.04f, r3 = roughness * 0.022f - 0.04f;
    const float a004 = std::min(r0 * r0, std::exp2(-9.28f * NoV)) * r0 + r1;
    return {-1.04f * a004 + r2, 1.04f * a004 + r3};
}

const EnvBRDFLut& EnvBRDFLut::instance() {
    static const EnvBRDFLut lut;  // C++11 magic static: built once, thread-safe
    return lut;
}

EnvBRDFLut::EnvBRDFLut() : mTexels(size_t(kNoVTexels) * kRoughnessTexels) {
    for (int j = 0; j < kRoughnessTexels; ++j)
        for (int i = 0; i < kNoVTexels; ++i) {
            const EnvBRDFTerms t = integrateEnvBRDF((i + 0.5f) / kNoVTexels,
                                                    (j + 0.5f) / kRoughnessTexels, kSamples);
            mTexels[size_t(j) * kNoVTexels + size_t(i)] = {unorm16(t.a), unorm16(t.b)};
        }
}

}  // namespace fp
