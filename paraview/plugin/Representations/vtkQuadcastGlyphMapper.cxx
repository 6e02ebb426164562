#include "vtkQuadcastGlyphMapper.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

// quadcast after VTK's headers (see vtkQuadcastGLContext.h).
#include "vtkQuadcastGLContext.h"
#include <quadcast/gl/quadric_renderer.hpp>
#include <quadcast/shapes.hpp>

using quadcast_paraview::SavedState;

struct vtkQuadcastGlyphMapper::Internals {
    // GL side: the renderer made in the render window last drawn in.
    quadcast_paraview::WindowRenderer<quadcast::gl::QuadricRenderer> gl;

    // Host side: the spheres of the last build, untransformed.
    std::vector<float> centers;  ///< xyz per glyph
    std::vector<float> radii;
    std::vector<double> tensors;  ///< 9 per glyph (rows), tensor ellipsoids only
    std::vector<float> bonds;  ///< p0 xyz, p1 xyz per bond (a segment of a line cell)
    std::vector<unsigned char> bond_colors;  ///< the colours of p0 and p1, as `colors`
    vtkIdType skipped_bonds = 0;  ///< segments of zero length or with a point that is not finite
    std::vector<unsigned char> colors;  ///< rgb + 1 per glyph of a mapped colour, 0 0 0 0 for the actor's colour
    vtkIdType skipped = 0;
    vtkIdType rejected = 0;  ///< tensor ellipsoids left out at the last upload
    double bounds[6] = {1, -1, 1, -1, 1, -1};
    vtkTimeStamp built;
    vtkMTimeType uploaded_matrix = 0;  ///< MTime of the actor matrix and build the renderer holds
    vtkTimeStamp upload_time;

};

vtkStandardNewMacro(vtkQuadcastGlyphMapper);

vtkQuadcastGlyphMapper::vtkQuadcastGlyphMapper() : Internal(std::make_unique<Internals>()) {}

vtkQuadcastGlyphMapper::~vtkQuadcastGlyphMapper() {
    // (GL objects are freed by ReleaseGraphicsResources while their context is current: see WindowRenderer.)
    this->SetTensorArray(nullptr);
}

void vtkQuadcastGlyphMapper::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    os << indent << "Glyphs: " << this->GetNumberOfGlyphs() << "\n" << indent << "SkippedPoints: " << this->GetSkippedPoints() << "\n";
}

vtkIdType vtkQuadcastGlyphMapper::GetNumberOfGlyphs() const { return static_cast<vtkIdType>(this->Internal->radii.size()) - this->Internal->rejected; }
vtkIdType vtkQuadcastGlyphMapper::GetSkippedPoints() const { return this->Internal->skipped + this->Internal->rejected; }

namespace {

/// The value a point contributes to its radius: the component, or the magnitude when the
/// component is outside the array (as vtkOpenGLPointGaussianMapper reads its scale array).
double scale_value(vtkDataArray* a, vtkIdType i, int component) {
    const int n = a->GetNumberOfComponents();
    if (n == 1) return a->GetComponent(i, 0);
    if (component >= 0 && component < n) return a->GetComponent(i, component);
    double s = 0;
    for (int c = 0; c < n; ++c) s += a->GetComponent(i, c) * a->GetComponent(i, c);
    return std::sqrt(s);
}

}  // namespace

namespace {

/// Half the extent along axis k of a sphere of radius r, or of the ellipsoid of tensor t (rows)
/// scaled by r, whose semi-axes are r times t's eigenvectors times their eigenvalues: for the
/// ellipsoid x = r T u, |u| <= 1, that is r |row k of T|.
double glyph_extent(double r, const double* t, int k) {
    if (!t) return r;
    return r * std::sqrt(t[3 * k] * t[3 * k] + t[3 * k + 1] * t[3 * k + 1] + t[3 * k + 2] * t[3 * k + 2]);
}

/// The polygonal blocks of a mapper input (one vtkPolyData, or a composite data set of them).
std::vector<vtkPolyData*> polydata_blocks(vtkDataObject* input) {
    std::vector<vtkPolyData*> blocks;
    if (auto* pd = vtkPolyData::SafeDownCast(input)) blocks.push_back(pd);
    if (auto* cd = vtkCompositeDataSet::SafeDownCast(input)) {
        vtkSmartPointer<vtkCompositeDataIterator> it;
        it.TakeReference(cd->NewIterator());
        for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
            if (auto* pd = vtkPolyData::SafeDownCast(it->GetCurrentDataObject())) blocks.push_back(pd);
    }
    return blocks;
}

}  // namespace

template <class Block, class Glyph>
vtkIdType vtkQuadcastGlyphMapper::ForEachGlyph(vtkDataObject* input, Block&& block, Glyph&& glyph) {
    vtkIdType skipped = 0;
    for (vtkPolyData* pd : polydata_blocks(input)) {
        const vtkIdType n = pd->GetNumberOfPoints();
        if (n == 0) continue;
        vtkDataArray* scale = this->ScaleArray ? pd->GetPointData()->GetArray(this->ScaleArray) : nullptr;
        vtkDataArray* tensors = nullptr;
        if (this->GlyphType == TENSOR_ELLIPSOID) {
            tensors = this->TensorArray ? pd->GetPointData()->GetArray(this->TensorArray) : nullptr;
            if (!tensors || (tensors->GetNumberOfComponents() != 9 && tensors->GetNumberOfComponents() != 6)) {
                vtkErrorMacro(<< "Quadric Glyphs: tensor ellipsoids need a point array of 9 or 6 (symmetric: xx yy zz xy yz xz) components as GlyphTensorArray; "
                              << (this->TensorArray ? this->TensorArray : "(none)") << (tensors ? " has " + std::to_string(tensors->GetNumberOfComponents()) : std::string(" is not a point array"))
                              << "; nothing drawn from this block");
                skipped += n;
                continue;
            }
        }
        block(pd);
        for (vtkIdType i = 0; i < n; ++i) {
            double r = this->ScaleFactor;
            if (scale) {
                double s = scale_value(scale, i, this->ScaleArrayComponent);
                if (this->ScaleFunction) s = this->ScaleFunction->GetValue(s);
                r *= s;
            }
            double p[3];
            pd->GetPoint(i, p);
            double t[9];
            bool ok = r > 0 && std::isfinite(r) && r < 3e38 && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
            if (tensors) {
                double v[9];
                tensors->GetTuple(i, v);
                if (tensors->GetNumberOfComponents() == 6) {  // (VTK's symmetric order: xx yy zz xy yz xz)
                    const double full[9] = {v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2]};
                    std::copy(full, full + 9, t);
                } else {
                    std::copy(v, v + 9, t);
                }
                for (double x : t) ok = ok && std::isfinite(x);
            }
            if (!ok) {
                ++skipped;
                continue;
            }
            glyph(i, p, r, tensors ? t : nullptr);
        }
    }
    return skipped;
}


void vtkQuadcastGlyphMapper::AddBonds(vtkPolyData* pd, vtkUnsignedCharArray* mapped, bool& any) {
    Internals& in = *this->Internal;
    vtkCellArray* lines = pd->GetLines();
    if (!lines || lines->GetNumberOfCells() == 0) return;
    const int comps = mapped ? mapped->GetNumberOfComponents() : 0;
    auto colour = [&](vtkIdType id) {
        if (!mapped) {
            in.bond_colors.insert(in.bond_colors.end(), {0, 0, 0, 0});
            return;
        }
        const unsigned char* c = mapped->GetPointer(id * comps);
        in.bond_colors.insert(in.bond_colors.end(), {c[0], c[comps >= 3 ? 1 : 0], c[comps >= 3 ? 2 : 0], 1});
    };
    const double r = this->BondRadius;
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    for (lines->InitTraversal(); lines->GetNextCell(npts, ids);) {
        for (vtkIdType k = 0; k + 1 < npts; ++k) {
            double a[3], b[3];
            pd->GetPoint(ids[k], a);
            pd->GetPoint(ids[k + 1], b);
            bool ok = !(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]);
            for (int j = 0; j < 3; ++j) ok = ok && std::isfinite(a[j]) && std::isfinite(b[j]);
            if (!ok) {
                ++in.skipped_bonds;
                continue;
            }
            for (double x : a) in.bonds.push_back(static_cast<float>(x));
            for (double x : b) in.bonds.push_back(static_cast<float>(x));
            colour(ids[k]);
            colour(ids[k + 1]);
            for (int j = 0; j < 3; ++j) {
                const double lo = std::min(a[j], b[j]) - r, hi = std::max(a[j], b[j]) + r;
                in.bounds[2 * j] = any ? std::min(in.bounds[2 * j], lo) : lo;
                in.bounds[2 * j + 1] = any ? std::max(in.bounds[2 * j + 1], hi) : hi;
            }
            any = true;
        }
    }
}

double* vtkQuadcastGlyphMapper::GetBounds() {
    Internals& in = *this->Internal;
    vtkDataObject* input = this->GetInputDataObject(0, 0);
    const vtkMTimeType newest = std::max<vtkMTimeType>({this->GetMTime(), input ? input->GetMTime() : 0,
                                                        this->LookupTable ? this->LookupTable->GetMTime() : 0,
                                                        this->ScaleFunction ? this->ScaleFunction->GetMTime() : 0});
    if (newest > in.built.GetMTime() || in.built.GetMTime() == 0) {
        in.centers.clear();
        in.radii.clear();
        in.tensors.clear();
        in.colors.clear();
        in.bonds.clear();
        in.bond_colors.clear();
        in.skipped_bonds = 0;
        vtkMath::UninitializeBounds(in.bounds);
        bool any = false;
        vtkUnsignedCharArray* mapped = nullptr;
        int comps = 0;
        in.skipped = this->ForEachGlyph(
            input,
            [&](vtkPolyData* pd) {
                int cell_flag = 0;
                mapped = this->ScalarVisibility ? this->MapScalars(pd, 1.0, cell_flag) : nullptr;
                if (mapped && (cell_flag != 0 || mapped->GetNumberOfTuples() != pd->GetNumberOfPoints())) mapped = nullptr;
                comps = mapped ? mapped->GetNumberOfComponents() : 0;
                if (this->BondRadius > 0) this->AddBonds(pd, mapped, any);
            },
            [&](vtkIdType i, const double p[3], double r, const double* t) {
                for (int k = 0; k < 3; ++k) in.centers.push_back(static_cast<float>(p[k]));
                in.radii.push_back(static_cast<float>(r));
                if (t) in.tensors.insert(in.tensors.end(), t, t + 9);
                if (mapped) {
                    const unsigned char* c = mapped->GetPointer(i * comps);  // (1 or 2 components: luminance)
                    in.colors.insert(in.colors.end(), {c[0], c[comps >= 3 ? 1 : 0], c[comps >= 3 ? 2 : 0], 1});
                } else {
                    in.colors.insert(in.colors.end(), {0, 0, 0, 0});
                }
                for (int k = 0; k < 3; ++k) {
                    const double e = glyph_extent(r, t, k);
                    in.bounds[2 * k] = any ? std::min(in.bounds[2 * k], p[k] - e) : p[k] - e;
                    in.bounds[2 * k + 1] = any ? std::max(in.bounds[2 * k + 1], p[k] + e) : p[k] + e;
                }
                any = true;
            });
        in.built.Modified();
    }
    std::copy(in.bounds, in.bounds + 6, this->Bounds);
    return this->Bounds;
}

void vtkQuadcastGlyphMapper::Render(vtkRenderer* ren, vtkActor* act) {
    Internals& in = *this->Internal;
    if (ren->GetSelector() != nullptr) return;  // (hardware selection: not drawn, see the header)
    vtkRenderWindow* win = ren->GetRenderWindow();
    this->GetBounds();  // (re)builds the spheres when the input, the colouring or the mapper changed
    bool fresh = false;
    std::string error;
    quadcast::gl::QuadricRenderer* renderer = in.gl.get(win, fresh, error);
    if (!error.empty()) vtkErrorMacro(<< "Quadric Glyphs cannot draw in this render window: " << error);
    if (!renderer) return;
    if (fresh) {
        in.upload_time = vtkTimeStamp();
        in.uploaded_matrix = 0;
    }

    // The actor's matrix moves the spheres: it must be a similarity (rotation, translation, one scale).
    vtkMatrix4x4* m = act->GetMatrix();
    double scale = 1;
    {
        double len[3];
        for (int c = 0; c < 3; ++c) len[c] = std::sqrt(m->GetElement(0, c) * m->GetElement(0, c) + m->GetElement(1, c) * m->GetElement(1, c) + m->GetElement(2, c) * m->GetElement(2, c));
        scale = len[0];
        bool similar = m->GetElement(3, 0) == 0 && m->GetElement(3, 1) == 0 && m->GetElement(3, 2) == 0 && m->GetElement(3, 3) == 1;
        for (int a = 0; a < 3 && similar; ++a) {
            if (std::fabs(len[a] - scale) > 1e-6 * scale) similar = false;
            for (int b = a + 1; b < 3; ++b) {
                double d = 0;
                for (int r = 0; r < 3; ++r) d += m->GetElement(r, a) * m->GetElement(r, b);
                if (std::fabs(d) > 1e-6 * scale * scale) similar = false;
            }
        }
        if (!similar || !(scale > 0)) {
            vtkErrorMacro(<< "Quadric Glyphs: the representation's Scale/Orientation/Position must scale all axes alike (spheres stay spheres); nothing drawn");
            return;
        }
    }
    double diffuse[3];
    act->GetProperty()->GetDiffuseColor(diffuse);
    const vtkMTimeType state = std::max({m->GetMTime(), act->GetProperty()->GetMTime()});
    if (in.upload_time.GetMTime() < in.built.GetMTime() || in.uploaded_matrix != state) {
        std::vector<quadcast::render::Primitive> prims;
        prims.reserve(in.radii.size());
        namespace qs = quadcast::shapes;
        qs::Appearance look;
        vtkIdType rejected = 0, rejected_bonds = 0;
        try {
            for (std::size_t i = 0; i < in.radii.size(); ++i) {
                double p[4] = {in.centers[3 * i], in.centers[3 * i + 1], in.centers[3 * i + 2], 1}, q[4];
                m->MultiplyPoint(p, q);
                const unsigned char* c = &in.colors[4 * i];
                look.color = c[3] ? glm::vec3(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f)
                                  : glm::vec3(static_cast<float>(diffuse[0]), static_cast<float>(diffuse[1]), static_cast<float>(diffuse[2]));
                const glm::vec3 center(static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2]));
                const float r = static_cast<float>(static_cast<double>(in.radii[i]) * scale);
                if (in.tensors.empty()) {
                    prims.push_back(qs::sphere(center, r, look));
                    continue;
                }
                // The actor's rotation R turns the tensor into R T R^T (its scale is in r).
                const double* t = &in.tensors[9 * i];
                glm::mat3 rotated(0.0f);  // (glm: [column][row])
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) {
                        double sum = 0;
                        for (int c = 0; c < 3; ++c)
                            for (int d = 0; d < 3; ++d) sum += m->GetElement(a, c) * t[3 * c + d] * m->GetElement(b, d);
                        rotated[b][a] = static_cast<float>(sum / (scale * scale));
                    }
                try {
                    prims.push_back(qs::tensor_ellipsoid(center, rotated, r, look));
                } catch (const std::invalid_argument&) {
                    ++rejected;  // (not positive definite, or too flat to bound)
                }
            }
            // Bonds: two capped half-cylinders per segment, each coloured as its own end point.
            const double bond_r = this->BondRadius * scale;
            for (std::size_t i = 0; bond_r > 0 && i < in.bonds.size() / 6; ++i) {
                glm::vec3 ends[2];
                for (int e = 0; e < 2; ++e) {
                    double p[4] = {in.bonds[6 * i + 3 * e], in.bonds[6 * i + 3 * e + 1], in.bonds[6 * i + 3 * e + 2], 1}, q[4];
                    m->MultiplyPoint(p, q);
                    ends[e] = glm::vec3(static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2]));
                }
                const glm::vec3 mid = 0.5f * (ends[0] + ends[1]);
                for (int e = 0; e < 2; ++e) {
                    const unsigned char* c = &in.bond_colors[8 * i + 4 * e];
                    look.color = c[3] ? glm::vec3(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f)
                                      : glm::vec3(static_cast<float>(diffuse[0]), static_cast<float>(diffuse[1]), static_cast<float>(diffuse[2]));
                    try {
                        prims.push_back(qs::cylinder(ends[e], mid, static_cast<float>(bond_r), qs::Ends::both, look));
                    } catch (const std::invalid_argument&) {
                        ++rejected_bonds;  // (a segment too short for float)
                    }
                }
            }
            renderer->set_primitives(prims);
            in.rejected = rejected;
            if (in.skipped_bonds + rejected_bonds > 0)
                vtkWarningMacro(<< "Quadric Glyphs: " << in.skipped_bonds + rejected_bonds << " line segments of zero length (or with a point that is not finite) are not drawn");
            if (rejected > 0)
                vtkWarningMacro(<< "Quadric Glyphs: " << rejected << " of " << in.radii.size()
                                << " tensors are not positive definite (or too flat to draw): those points are not drawn");
        } catch (const std::exception& e) {
            vtkErrorMacro(<< "Quadric Glyphs: " << e.what());
            return;
        }
        in.upload_time.Modified();
        in.uploaded_matrix = state;
    }

    // The view's camera: VTK's view and projection matrices for this viewport's aspect.
    quadcast::render::Camera camera;
    quadcast::render::Light light;
    quadcast::render::RenderOptions options;
    if (!quadcast_paraview::view_camera(ren, camera, light, options, error)) {
        if (!error.empty()) vtkErrorMacro(<< "Quadric Glyphs: " << error);
        return;
    }
    options.occlusion_culling = true;  // (frustum and occlusion culling among the glyphs where their expected overlap reaches RenderOptions::occlusion_min_overlap; the same picture)

    SavedState saved(in.gl.api());
    try {
        renderer->draw_primitives(camera, light, options, false);
    } catch (const std::exception& e) {
        vtkErrorMacro(<< "Quadric Glyphs: " << e.what());
    }
}

void vtkQuadcastGlyphMapper::ReleaseGraphicsResources(vtkWindow* win) {
    Internals& in = *this->Internal;
    // VTK calls this with the window's context current (as for its own mappers' GL objects).
    in.gl.release(win);
    this->Superclass::ReleaseGraphicsResources(win);
}
