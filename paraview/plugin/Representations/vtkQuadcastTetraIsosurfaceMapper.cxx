#include "vtkQuadcastTetraIsosurfaceMapper.h"

#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "vtkActor.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

// quadcast after VTK's headers (see vtkQuadcastGLContext.h).
#include "vtkQuadcastGLContext.h"
#include <quadcast/bb/quadric_form.hpp>
#include <quadcast/gl/quadric_renderer.hpp>
#include <quadcast/shapes.hpp>

namespace {

/// VTK_QUADRATIC_TETRA's edge nodes in quadcast's edge order (bb::quadratic_edges: 01 02 03 12 13
/// 23); VTK puts the midpoints of 01 12 20 03 13 23 at nodes 4..9.
constexpr int vtk_edge_node[6] = {4, 6, 7, 5, 8, 9};

}  // namespace

struct vtkQuadcastTetraIsosurfaceMapper::Internals {
    quadcast_paraview::WindowRenderer<quadcast::gl::QuadricRenderer> gl;
    vtkTimeStamp built;                ///< when the pieces were last made
    vtkMTimeType built_state = 0;      ///< the actor's matrix and property MTime they were made with
    vtkIdType pieces = 0, skipped = 0;
};

vtkStandardNewMacro(vtkQuadcastTetraIsosurfaceMapper);

vtkQuadcastTetraIsosurfaceMapper::vtkQuadcastTetraIsosurfaceMapper() : Internal(std::make_unique<Internals>()) {}

vtkQuadcastTetraIsosurfaceMapper::~vtkQuadcastTetraIsosurfaceMapper() { this->SetScalarArray(nullptr); }

int vtkQuadcastTetraIsosurfaceMapper::FillInputPortInformation(int, vtkInformation* info) {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
    return 1;
}

void vtkQuadcastTetraIsosurfaceMapper::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    os << indent << "Isovalue: " << this->Isovalue << "\n"
       << indent << "ScalarArray: " << (this->ScalarArray ? this->ScalarArray : "(active scalars)") << "\n"
       << indent << "Pieces: " << this->Internal->pieces << "\n"
       << indent << "SkippedCells: " << this->Internal->skipped << "\n";
}

vtkIdType vtkQuadcastTetraIsosurfaceMapper::GetNumberOfPieces() const { return this->Internal->pieces; }
vtkIdType vtkQuadcastTetraIsosurfaceMapper::GetNumberOfSkippedCells() const { return this->Internal->skipped; }

double* vtkQuadcastTetraIsosurfaceMapper::GetBounds() {
    vtkMath::UninitializeBounds(this->Bounds);
    auto* grid = vtkUnstructuredGrid::SafeDownCast(this->GetInputDataObject(0, 0));
    if (grid && grid->GetNumberOfPoints() > 0) grid->GetBounds(this->Bounds);
    return this->Bounds;
}

void vtkQuadcastTetraIsosurfaceMapper::Render(vtkRenderer* ren, vtkActor* act) {
    Internals& in = *this->Internal;
    if (ren->GetSelector() != nullptr) return;  // (hardware selection: not drawn)
    bool fresh = false;
    std::string error;
    quadcast::gl::QuadricRenderer* renderer = in.gl.get(ren->GetRenderWindow(), fresh, error);
    if (!error.empty()) vtkErrorMacro(<< "Tetra Isosurface cannot draw in this render window: " << error);
    if (!renderer) return;

    // The pieces, made again when the input, a property, the actor's matrix or colour changed (the
    // actor's affine matrix moves the nodes: a Lagrange element stays one under an affine map).
    auto* grid = vtkUnstructuredGrid::SafeDownCast(this->GetInputDataObject(0, 0));
    vtkMatrix4x4* m = act->GetMatrix();
    const vtkMTimeType state = std::max(m->GetMTime(), act->GetProperty()->GetMTime());
    const vtkMTimeType newest = std::max(this->GetMTime(), grid ? grid->GetMTime() : 0);
    if (fresh || newest > in.built.GetMTime() || state != in.built_state) {
        in.built.Modified();
        in.built_state = state;
        in.pieces = 0;
        in.skipped = 0;
        std::vector<quadcast::render::Primitive> prims;
        const bool affine = m->GetElement(3, 0) == 0 && m->GetElement(3, 1) == 0 && m->GetElement(3, 2) == 0 && m->GetElement(3, 3) == 1;
        vtkDataArray* a = !grid ? nullptr : this->ScalarArray ? grid->GetPointData()->GetArray(this->ScalarArray) : grid->GetPointData()->GetScalars();
        if (grid && grid->GetNumberOfCells() > 0 && (!a || a->GetNumberOfComponents() != 1)) {
            vtkErrorMacro(<< "Tetra Isosurface: the point array " << (this->ScalarArray ? this->ScalarArray : "(active scalars)")
                          << (a ? " has " + std::to_string(a->GetNumberOfComponents()) + " components; one is needed" : std::string(" does not exist"))
                          << "; nothing drawn");
            a = nullptr;
        } else if (!affine) {
            vtkErrorMacro(<< "Tetra Isosurface: the actor's matrix is not affine; nothing drawn");
            a = nullptr;
        } else if (!std::isfinite(this->Isovalue)) {
            vtkErrorMacro(<< "Tetra Isosurface: the isovalue is not finite; nothing drawn");
            a = nullptr;
        }
        if (grid && a) {
            auto* ghosts = vtkUnsignedCharArray::SafeDownCast(grid->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
            double diffuse[3];
            act->GetProperty()->GetDiffuseColor(diffuse);
            quadcast::shapes::Appearance look;
            look.color = glm::vec3(static_cast<float>(diffuse[0]), static_cast<float>(diffuse[1]), static_cast<float>(diffuse[2]));
            vtkIdType other = 0, curved = 0, flat = 0, bad = 0;
            for (vtkIdType c = 0, n = grid->GetNumberOfCells(); c < n; ++c) {
                if (ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL)) continue;  // (its owner draws it)
                const int type = grid->GetCellType(c);
                if (type != VTK_TETRA && type != VTK_QUADRATIC_TETRA) {
                    ++other;
                    continue;
                }
                vtkIdType npts = 0;
                const vtkIdType* ids = nullptr;
                grid->GetCellPoints(c, npts, ids);
                if (npts != (type == VTK_TETRA ? 4 : 10)) {
                    ++other;
                    continue;
                }
                quadcast::Vec3<double> x[10];
                double v[10];
                bool finite = true;
                for (vtkIdType k = 0; k < npts; ++k) {
                    double p[4] = {0, 0, 0, 1}, q[4];
                    grid->GetPoint(ids[k], p);
                    m->MultiplyPoint(p, q);
                    x[k] = quadcast::Vec3<double>{{q[0], q[1], q[2]}};
                    v[k] = a->GetComponent(ids[k], 0);
                    finite = finite && std::isfinite(v[k]) && std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
                }
                if (!finite) {
                    ++bad;
                    continue;
                }
                const quadcast::Vec3<double> corners[4] = {x[0], x[1], x[2], x[3]};
                const double corner[4] = {v[0], v[1], v[2], v[3]};
                double mid[6];
                if (type == VTK_QUADRATIC_TETRA) {
                    quadcast::Vec3<double> edge_nodes[6];
                    for (int e = 0; e < 6; ++e) {
                        edge_nodes[e] = x[vtk_edge_node[e]];
                        mid[e] = v[vtk_edge_node[e]];
                    }
                    const double longest = quadcast::tet_shape(corners).longest;
                    if (!(quadcast::bb::edge_node_offset(corners, edge_nodes).distance <= quadcast::bb::straight_edge_tolerance * longest)) {
                        ++curved;
                        continue;
                    }
                }
                const quadcast::bb::ElementIsosurface<double> iso =
                    quadcast::bb::element_isosurface(corners, corner, type == VTK_QUADRATIC_TETRA ? mid : nullptr, this->Isovalue);
                if (!iso.crosses) continue;
                glm::dmat4 q;
                for (int j = 0; j < 4; ++j)
                    for (int i = 0; i < 4; ++i) q[j][i] = iso.q.q[j][i];
                quadcast::shapes::TetrahedronBound bound{};
                for (int k = 0; k < 4; ++k)
                    bound.corners[static_cast<std::size_t>(k)] =
                        glm::vec3(static_cast<float>(corners[k][0]), static_cast<float>(corners[k][1]), static_cast<float>(corners[k][2]));
                try {
                    prims.push_back(quadcast::shapes::quadric(q, bound, look));
                } catch (const std::invalid_argument&) {
                    ++flat;  // (flat, or too flat for float clip planes)
                }
            }
            in.skipped = other + curved + flat + bad;
            if (in.skipped > 0)
                vtkWarningMacro(<< "Tetra Isosurface: cells not drawn: " << other << " not linear or quadratic tetrahedra, " << curved
                                << " curved quadratic tetrahedra (an edge node off its edge's midpoint), " << flat << " flat tetrahedra, " << bad
                                << " with a value or point that is not finite");
        }
        try {
            renderer->set_primitives(prims);
            in.pieces = static_cast<vtkIdType>(prims.size());
        } catch (const std::exception& e) {
            vtkErrorMacro(<< "Tetra Isosurface: " << e.what());
            renderer->set_primitives({});
            in.pieces = 0;
        }
    }
    if (in.pieces == 0) return;

    quadcast::render::Camera camera;
    quadcast::render::Light light;
    quadcast::render::RenderOptions options;
    if (!quadcast_paraview::view_camera(ren, camera, light, options, error)) {
        if (!error.empty()) vtkErrorMacro(<< "Tetra Isosurface: " << error);
        return;
    }
    options.culling = false;           // (isosurface pieces have no outside: either side may face the eye, as the MSH scenes draw them)
    options.occlusion_culling = true;  // (frustum and occlusion culling among the pieces where their expected overlap reaches RenderOptions::occlusion_min_overlap; the same picture)
    quadcast_paraview::SavedState saved(in.gl.api());
    try {
        renderer->draw_primitives(camera, light, options, false);
    } catch (const std::exception& e) {
        vtkErrorMacro(<< "Tetra Isosurface: " << e.what());
    }
}

void vtkQuadcastTetraIsosurfaceMapper::ReleaseGraphicsResources(vtkWindow* win) {
    this->Internal->gl.release(win);
    this->Superclass::ReleaseGraphicsResources(win);
}
