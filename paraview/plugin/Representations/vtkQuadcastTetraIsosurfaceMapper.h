// vtkQuadcastTetraIsosurfaceMapper -- the isosurface of a tetrahedral mesh's linear or quadratic field, exact per element
#ifndef vtkQuadcastTetraIsosurfaceMapper_h
#define vtkQuadcastTetraIsosurfaceMapper_h

#include <memory>

#include "QuadcastRepresentationsModule.h"  // for the export macro
#include "vtkMapper.h"

/// Draws the isosurface Isovalue of an unstructured grid's point array (ScalarArray, one
/// component) on its VTK_TETRA (linear) and VTK_QUADRATIC_TETRA (10 nodes: quadratic) cells: on
/// each element the field is a polynomial of degree 1 or 2, so its isosurface there is a quadric
/// clipped to the tetrahedron (quadcast::bb::element_isosurface, the same construction as the
/// MSH reader's), ray cast per pixel by quadcast::gl::QuadricRenderer in the render window's own
/// context and depth buffer. Both sides of the surface are lit (an isosurface has no outside).
///
/// Not drawn, and counted in a warning: cells of other types, ghost cells (the rank that owns
/// them draws them), curved quadratic elements (an edge node off its edge's midpoint by more
/// than 1e-6 of the element's size: their isosurface is not a quadric), flat elements.
/// Colour: the actor's diffuse colour; one white headlight. The actor may move, rotate and scale
/// the mesh uniformly; a scale that differs between axes is an error (nothing drawn).
class QUADCASTREPRESENTATIONS_EXPORT vtkQuadcastTetraIsosurfaceMapper : public vtkMapper {
public:
    static vtkQuadcastTetraIsosurfaceMapper* New();
    vtkTypeMacro(vtkQuadcastTetraIsosurfaceMapper, vtkMapper);
    void PrintSelf(ostream& os, vtkIndent indent) override;

    vtkSetMacro(Isovalue, double);
    vtkGetMacro(Isovalue, double);
    /// The point array whose isosurface is drawn (null: the active scalars).
    vtkSetStringMacro(ScalarArray);
    vtkGetStringMacro(ScalarArray);

    void Render(vtkRenderer* ren, vtkActor* act) override;
    void ReleaseGraphicsResources(vtkWindow* win) override;
    /// The input's bounds, untransformed (the actor applies its matrix); before the view has
    /// connected the input: uninitialized (vtkMapper's would update an unconnected input).
    double* GetBounds() override;
    void GetBounds(double bounds[6]) override { this->vtkAbstractMapper3D::GetBounds(bounds); }
    bool HasTranslucentPolygonalGeometry() override { return false; }
    bool HasOpaqueGeometry() override { return true; }

    /// Of the last build: the elements whose isosurface piece is drawn, and the cells left out.
    vtkIdType GetNumberOfPieces() const;
    vtkIdType GetNumberOfSkippedCells() const;

protected:
    vtkQuadcastTetraIsosurfaceMapper();
    ~vtkQuadcastTetraIsosurfaceMapper() override;
    int FillInputPortInformation(int port, vtkInformation* info) override;

private:
    vtkQuadcastTetraIsosurfaceMapper(const vtkQuadcastTetraIsosurfaceMapper&) = delete;
    void operator=(const vtkQuadcastTetraIsosurfaceMapper&) = delete;
    struct Internals;
    std::unique_ptr<Internals> Internal;
    double Isovalue = 0;
    char* ScalarArray = nullptr;
};

#endif
