#pragma once
// Watertight ray-triangle intersection (Woop, Benthin, Wald 2013), on triangles blended to the
// ray's time. The ray is sheared so it runs along +z; edge functions are evaluated in that frame
// and recomputed in double precision when one is exactly zero, so a ray through a shared edge or
// vertex hits at least one of the triangles, and never falls through the crack between them.

#include "pipeline/core/ray.h"

namespace patchsim {

struct ShearedRay {
    Vec3 origin{0.0f};
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
};

ShearedRay shearRay(const Ray& ray);

struct TriangleHit {
    float lambda;      // ray parameter
    float b0, b1, b2;  // barycentric weights of vertices 0, 1, 2
};

// Hit in [lambdaMin, lambdaMax] (both inclusive); both faces count.
bool intersectTriangle(const ShearedRay& ray, const Vec3& a, const Vec3& b, const Vec3& c,
                       float lambdaMin, float lambdaMax, TriangleHit& hit);

}  // namespace patchsim
