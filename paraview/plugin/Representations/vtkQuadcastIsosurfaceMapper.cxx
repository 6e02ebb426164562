#include "vtkQuadcastIsosurfaceMapper.h"

#include <cmath>
#include <exception>
#include <string>

#include "vtkActor.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"

// quadcast after VTK's headers (see vtkQuadcastGLContext.h).
#include "vtkQuadcastGLContext.h"
#include <quadcast/gl/isosurface_renderer.hpp>
#include <quadcast/render/spline_cpu_renderer.hpp>

namespace {

namespace qr = quadcast::render;

qr::VolumeScheme scheme_of(int s) {
    return s == vtkQuadcastIsosurfaceMapper::S31 ? qr::VolumeScheme::s31 : s == vtkQuadcastIsosurfaceMapper::TRILINEAR ? qr::VolumeScheme::trilinear : qr::VolumeScheme::qss;
}

bool valid_extent(const int e[6]) { return e[0] <= e[1] && e[2] <= e[3] && e[4] <= e[5]; }

/// The cubes (cells) of a piece drawn, in the index space of its extent `ext` (index 0 = its
/// first sample), from its own extent and the whole image's (see the class comment).
qr::IndexBox drawn_box(const int ext[6], const int own[6], const int whole[6], bool trilinear) {
    qr::IndexBox b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = own[2 * a] - ext[2 * a];
        const bool last = own[2 * a + 1] >= whole[2 * a + 1];
        b.hi[a] = own[2 * a + 1] - ext[2 * a] - (trilinear || !last ? 1 : 0);
    }
    return b;
}

/// The volume's geometry without its data: what `world_box` needs (bounds before a preparation).
qr::VolumeModel geometry_of(vtkImageData* image, int scheme, const int own[6], const int whole[6]) {
    qr::VolumeModel m;
    m.scheme = scheme_of(scheme);
    int ext[6];
    image->GetExtent(ext);
    double origin[3], spacing[3];
    image->GetOrigin(origin);
    image->GetSpacing(spacing);
    m.nx = ext[1] - ext[0] + 1;
    m.ny = ext[3] - ext[2] + 1;
    m.nz = ext[5] - ext[4] + 1;
    for (int a = 0; a < 3; ++a) {
        m.spacing[a] = spacing[a];
        m.origin[a] = origin[a] + spacing[a] * ext[2 * a];  // (the world position of the piece's first sample)
    }
    m.drawn = drawn_box(ext, valid_extent(own) ? own : ext, valid_extent(whole) ? whole : ext, m.scheme == qr::VolumeScheme::trilinear);
    return m;
}

}  // namespace

struct vtkQuadcastIsosurfaceMapper::Internals {
    quadcast_paraview::WindowRenderer<quadcast::gl::IsosurfaceRenderer> gl;
    qr::VolumeModel model;        ///< the prepared piece (origin, spacing and colour set at each render from the actor)
    bool ready = false;           ///< `model` holds a prepared volume
    vtkTimeStamp prepared;        ///< when `model` was (re)prepared, or found not drawable
    vtkTimeStamp uploaded;        ///< when the renderer last took `model`
    vtkIdType drawn = 0;          ///< elements the last render drew
};

vtkStandardNewMacro(vtkQuadcastIsosurfaceMapper);

vtkQuadcastIsosurfaceMapper::vtkQuadcastIsosurfaceMapper() : Internal(std::make_unique<Internals>()) {}

vtkQuadcastIsosurfaceMapper::~vtkQuadcastIsosurfaceMapper() {
    // (GL objects are freed by ReleaseGraphicsResources while their context is current: see WindowRenderer.)
    this->SetScalarArray(nullptr);
}

int vtkQuadcastIsosurfaceMapper::FillInputPortInformation(int, vtkInformation* info) {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    return 1;
}

void vtkQuadcastIsosurfaceMapper::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    os << indent << "Scheme: " << qr::volume_scheme_name(scheme_of(this->Scheme)) << "\n"
       << indent << "Isovalue: " << this->Isovalue << "\n"
       << indent << "ScalarArray: " << (this->ScalarArray ? this->ScalarArray : "(active scalars)") << "\n"
       << indent << "ActiveCubes: " << this->GetNumberOfActiveCubes() << "\n";
}

vtkIdType vtkQuadcastIsosurfaceMapper::GetNumberOfActiveCubes() const {
    return this->Internal->ready ? static_cast<vtkIdType>(this->Internal->model.active) : 0;
}

vtkIdType vtkQuadcastIsosurfaceMapper::GetNumberOfDrawnElements() const {
    return this->Internal->drawn;
}

void vtkQuadcastIsosurfaceMapper::DrawnBounds(vtkImageData* image, int scheme, const int owned[6], const int whole[6], double bounds[6]) {
    vtkMath::UninitializeBounds(bounds);
    if (!image || image->GetNumberOfPoints() == 0) return;
    const qr::VolumeModel g = geometry_of(image, scheme, owned, whole);
    if (g.draws_nothing()) return;
    quadcast::Vec3<double> lo{}, hi{};
    g.world_box(lo, hi);
    for (int a = 0; a < 3; ++a) {
        bounds[2 * a] = lo[a];
        bounds[2 * a + 1] = hi[a];
    }
}

double* vtkQuadcastIsosurfaceMapper::GetBounds() {
    DrawnBounds(vtkImageData::SafeDownCast(this->GetInputDataObject(0, 0)), this->Scheme, this->OwnedExtent, this->WholeExtent, this->Bounds);
    return this->Bounds;
}

bool vtkQuadcastIsosurfaceMapper::Prepare() {
    Internals& in = *this->Internal;
    auto* image = vtkImageData::SafeDownCast(this->GetInputDataObject(0, 0));
    const vtkMTimeType newest = std::max(this->GetMTime(), image ? image->GetMTime() : 0);
    if (in.prepared.GetMTime() >= newest && in.prepared.GetMTime() != 0) return in.ready;
    in.prepared.Modified();
    in.ready = false;
    in.model = qr::VolumeModel{};
    if (!image || image->GetNumberOfPoints() == 0) return false;
    vtkMatrix3x3* dir = image->GetDirectionMatrix();
    if (dir && !dir->IsIdentity()) {
        vtkErrorMacro(<< "Spline Isosurface: the image has a direction matrix other than the identity; nothing drawn");
        return false;
    }
    vtkDataArray* a = this->ScalarArray ? image->GetPointData()->GetArray(this->ScalarArray) : image->GetPointData()->GetScalars();
    if (!a || a->GetNumberOfComponents() != 1) {
        vtkErrorMacro(<< "Spline Isosurface: the point array " << (this->ScalarArray ? this->ScalarArray : "(active scalars)")
                      << (a ? " has " + std::to_string(a->GetNumberOfComponents()) + " components; one is needed" : std::string(" does not exist"))
                      << "; nothing drawn");
        return false;
    }
    if (!std::isfinite(this->Isovalue)) {
        vtkErrorMacro(<< "Spline Isosurface: the isovalue is not finite; nothing drawn");
        return false;
    }
    qr::VolumeModel g = geometry_of(image, this->Scheme, this->OwnedExtent, this->WholeExtent);
    if (g.draws_nothing()) return false;  // (a piece with no cube of its own)
    try {
        quadcast::spline::Volume<float> vol(g.nx, g.ny, g.nz);
        const vtkIdType n = a->GetNumberOfTuples();
        if (n != static_cast<vtkIdType>(vol.data.size())) throw std::runtime_error("the array's length is not the image's point count");
        vtkIdType bad = 0;
        for (vtkIdType i = 0; i < n; ++i) {
            const double v = a->GetComponent(i, 0);
            bad += !(std::isfinite(v) && std::fabs(v) < 3e38);
            vol.data[static_cast<std::size_t>(i)] = static_cast<float>(v);  // (VTK's point order is i fastest, as quadcast's)
        }
        if (bad > 0) throw std::runtime_error(std::to_string(bad) + " samples are not finite (or beyond float)");
        in.model = qr::prepare_volume_piece(vol, g.origin, g.spacing, g.scheme, static_cast<float>(this->Isovalue), g.drawn, g.color, 0,
                                            /*cpu_coefficients=*/false);
    } catch (const std::exception& e) {
        in.model = qr::VolumeModel{};
        vtkErrorMacro(<< "Spline Isosurface: " << e.what() << "; nothing drawn");
        return false;
    }
    in.ready = true;
    return true;
}

void vtkQuadcastIsosurfaceMapper::Render(vtkRenderer* ren, vtkActor* act) {
    Internals& in = *this->Internal;
    if (ren->GetSelector() != nullptr) return;  // (hardware selection: not drawn)
    vtkRenderWindow* win = ren->GetRenderWindow();
    const bool ready = this->Prepare();
    bool fresh = false;
    std::string error;
    quadcast::gl::IsosurfaceRenderer* renderer = in.gl.get(win, fresh, error);
    if (!error.empty()) vtkErrorMacro(<< "Spline Isosurface cannot draw in this render window: " << error);
    if (fresh) in.uploaded = vtkTimeStamp();
    if (!renderer || !ready) return;

    // The actor may translate and scale each axis (a positive factor): the volume's origin and
    // spacing move with it; a rotation is refused.
    vtkMatrix4x4* m = act->GetMatrix();
    bool axis_aligned = m->GetElement(3, 0) == 0 && m->GetElement(3, 1) == 0 && m->GetElement(3, 2) == 0 && m->GetElement(3, 3) == 1;
    for (int r = 0; r < 3; ++r) {
        axis_aligned = axis_aligned && m->GetElement(r, r) > 0;
        for (int c = 0; c < 3; ++c)
            if (r != c && std::fabs(m->GetElement(r, c)) > 1e-12 * std::fabs(m->GetElement(r, r))) axis_aligned = false;
    }
    if (!axis_aligned) {
        vtkErrorMacro(<< "Spline Isosurface: the representation's Orientation must be 0 0 0 and its Scale positive (the volume stays axis-aligned); nothing drawn");
        return;
    }
    const qr::VolumeModel g = geometry_of(vtkImageData::SafeDownCast(this->GetInputDataObject(0, 0)), this->Scheme, this->OwnedExtent, this->WholeExtent);
    for (int a = 0; a < 3; ++a) {
        in.model.spacing[a] = g.spacing[a] * m->GetElement(a, a);
        in.model.origin[a] = g.origin[a] * m->GetElement(a, a) + m->GetElement(a, 3);
    }
    double diffuse[3];
    act->GetProperty()->GetDiffuseColor(diffuse);
    for (int a = 0; a < 3; ++a) in.model.color[a] = static_cast<float>(diffuse[a]);
    if (in.uploaded.GetMTime() < in.prepared.GetMTime()) {
        try {
            renderer->clear();
            renderer->add_volume(in.model);
        } catch (const std::exception& e) {
            vtkErrorMacro(<< "Spline Isosurface: " << e.what());
            return;
        }
        in.uploaded.Modified();
    }

    qr::Camera camera;
    qr::Light light;
    qr::RenderOptions options;
    if (!quadcast_paraview::view_camera(ren, camera, light, options, error)) {
        if (!error.empty()) vtkErrorMacro(<< "Spline Isosurface: " << error);
        return;
    }
    options.occlusion_culling = true;  // (nearest cubes first, the later phases tested against their depth; the same picture)
    quadcast_paraview::SavedState saved(in.gl.api());
    try {
        renderer->draw(camera, light, options, false);
        in.drawn = static_cast<vtkIdType>(renderer->stats(0).elements);
    } catch (const std::exception& e) {
        vtkErrorMacro(<< "Spline Isosurface: " << e.what());
    }
}

void vtkQuadcastIsosurfaceMapper::ReleaseGraphicsResources(vtkWindow* win) {
    Internals& in = *this->Internal;
    in.gl.release(win);
    this->Superclass::ReleaseGraphicsResources(win);
}
