// quadcast/codegen/src/registry.cpp -- the list of every kernel the project emits
#include "quadcast/codegen/generate.hpp"

#include "kernels/quadric_kernels.hpp"
#include "kernels/ray_kernels.hpp"
#include "kernels/bounds_kernels.hpp"
#include "kernels/render_kernels.hpp"
#include "kernels/spline_kernels.hpp"
#include "kernels/spline_render_kernels.hpp"
#include "kernels/slim_kernels.hpp"

namespace quadcast::codegen {

const std::vector<KernelDef>& registry() {
    using namespace kernels;
    static const std::vector<KernelDef> all = {
        make_kernel<QuadricEvaluate>(),
        make_kernel<QuadricHalfGradient>(),
        make_kernel<QuadricTransform>(),
        make_kernel<QuadricToEye>(),
        make_kernel<RayCoefficientsKernel>(),
        make_kernel<RayQuadraticLocalKernel>(),
        make_kernel<FrontRootKernel<RootFormula::stable>>(),
        make_kernel<FrontRootKernel<RootFormula::classic>>(),
        make_kernel<FrontRootKernel<RootFormula::stoll>>(),
        make_kernel<RootsNearFirstKernel>(),
        make_kernel<CullSphereKernel>(),
        make_kernel<CullTetKernel>(),
        make_kernel<InsideTetKernel>(),
        make_kernel<BilinearLocalKernel>(),
        make_kernel<SiggBBoxKernel>(),
        make_kernel<SlabBBoxKernel<false>>(),
        make_kernel<SlabBBoxKernel<true>>(),
        make_kernel<WindowRayKernel>(),
        make_kernel<SphereQuadKernel>(),
        make_kernel<PrimitiveBoundKernel<false>>(),
        make_kernel<PrimitiveBoundKernel<true>>(),
        make_kernel<ClipPositionKernel>(),
        make_kernel<PrimitiveRectKernel<RectBound::sphere>>(),
        make_kernel<PrimitiveRectKernel<RectBound::ellipsoid>>(),
        make_kernel<PrimitiveRectKernel<RectBound::slab>>(),
        make_kernel<PrimitiveQuadSlabKernel>(),
        make_kernel<PrimitiveQuadTetraKernel>(),
        make_kernel<PrimitiveCullKernel>(),
        make_kernel<FragmentRayKernel<false>>(),
        make_kernel<FragmentRayKernel<true>>(),
        make_kernel<FragmentCastKernel<CastOptions{true, false, false}>>(),
        make_kernel<FragmentCastKernel<CastOptions{false, false, false}>>(),
        make_kernel<FragmentCastKernel<CastOptions{true, true, false}>>(),
        make_kernel<FragmentCastKernel<CastOptions{false, true, false}>>(),
        make_kernel<FragmentCastKernel<CastOptions{true, false, true}>>(),
        make_kernel<FragmentCastKernel<CastOptions{false, false, true}>>(),
        make_kernel<FragmentCastKernel<CastOptions{true, false, false, true}>>(),
        make_kernel<FragmentCastKernel<CastOptions{false, false, false, true}>>(),
        make_kernel<FragmentSphereKernel<true>>(),
        make_kernel<FragmentSphereKernel<false>>(),
        make_kernel<ShadeKernel>(),
        make_kernel<SilhouetteKernel>(),
        make_kernel<PcfFirst8Kernel>(),
        make_kernel<Pcf64Kernel>(),
        make_kernel<PcfSampleTexelKernel>(),
        make_kernel<NeighbourTexelKernel>(),
        make_kernel<OccluderDepthKernel>(),
        make_kernel<NearestDistanceKernel>(),
        make_kernel<DepthDistanceKernel>(),
        make_kernel<OccluderEllipseKernel>(),
        make_kernel<OccluderChainCountKernel>(),
        make_kernel<OccluderChainDiskKernel>(),
        make_kernel<OccluderCornerKernel>(),
        make_kernel<EllipseCoversKernel>(),
        make_kernel<PixelSpanKernel>(),
        make_kernel<ShadowCoordKernel>(),
        make_kernel<ShadeShadowedKernel>(),
        make_kernel<ReflectViewKernel>(),
        make_kernel<EnvironmentTexelKernel>(),
        make_kernel<EnvironmentTexelsKernel>(),
        make_kernel<EnvironmentMixKernel>(),
        make_kernel<SplineTet0CoefficientsKernel<2>>(),
        make_kernel<SplineTet0CoefficientsKernel<3>>(),
        make_kernel<SplineBarycentricKernel>(),
        make_kernel<RestrictKernel<2>>(),
        make_kernel<RestrictKernel<3>>(),
        make_kernel<RestrictFromFirstStepKernel>(),
        make_kernel<QuadraticFirstRootKernel>(),
        make_kernel<CubicFirstRootKernel>(),
        make_kernel<CubicFirstRootNewtonKernel>(),
        make_kernel<ValueGradientKernel<2>>(),
        make_kernel<ValueGradientKernel<3>>(),
        make_kernel<SplinePieceHitKernel<2>>(),
        make_kernel<SplinePieceHitKernel<3>>(),
        make_kernel<TrilinearCellHitKernel>(),
        make_kernel<SplineCellVertexKernel<false>>(),
        make_kernel<SplineCellVertexKernel<true>>(),
        make_kernel<ClipOutsideKernel>(),
        make_kernel<SplineFragmentKernel<2>>(),
        make_kernel<SplineFragmentKernel<3>>(),
        make_kernel<TrilinearFragmentKernel>(),
        make_kernel<PixelRayKernel>(),
        make_kernel<SlimWeightKernel>(),
        make_kernel<SlimFragmentKernel<true>>(),
        make_kernel<SlimFragmentKernel<false>>(),
        make_kernel<SlimTermsKernel>(),
        make_kernel<SlimResolveKernel>(),
    };
    return all;
}

}  // namespace quadcast::codegen
