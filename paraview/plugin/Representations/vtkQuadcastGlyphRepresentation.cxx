#include "vtkQuadcastGlyphRepresentation.h"

#include "vtkActor.h"
#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPVRenderView.h"
#include "vtkObjectFactory.h"
#include "vtkQuadcastGlyphMapper.h"

vtkStandardNewMacro(vtkQuadcastGlyphRepresentation);

vtkQuadcastGlyphRepresentation::vtkQuadcastGlyphRepresentation() {
    this->Mapper = vtkSmartPointer<vtkQuadcastGlyphMapper>::New();
    this->Actor->SetMapper(this->Mapper);
    this->SetUseScaleFunction(false);
}

vtkQuadcastGlyphRepresentation::~vtkQuadcastGlyphRepresentation() = default;

vtkQuadcastGlyphMapper* vtkQuadcastGlyphRepresentation::GetGlyphMapper() { return vtkQuadcastGlyphMapper::SafeDownCast(this->Mapper); }

void vtkQuadcastGlyphRepresentation::SetGlyphType(int type) { this->GetGlyphMapper()->SetGlyphType(type); }

void vtkQuadcastGlyphRepresentation::SelectTensorArray(int, int, int, int, const char* name) {
    this->GetGlyphMapper()->SetTensorArray(name && name[0] ? name : nullptr);
}

void vtkQuadcastGlyphRepresentation::PrintSelf(ostream& os, vtkIndent indent) { this->Superclass::PrintSelf(os, indent); }

int vtkQuadcastGlyphRepresentation::ProcessViewRequest(vtkInformationRequestKey* request_type, vtkInformation* inInfo, vtkInformation* outInfo) {
    if (!this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo)) return 0;
    if (request_type == vtkPVView::REQUEST_UPDATE() && this->ProcessedData) {
        // This rank's points' bounds grown by their radii (the view gathers the ranks').
        double bounds[6];
        this->GetGlyphMapper()->ComputeGlyphBounds(this->ProcessedData, bounds);
        if (vtkMath::AreBoundsInitialized(bounds)) {
            vtkNew<vtkMatrix4x4> matrix;
            this->Actor->GetMatrix(matrix.GetPointer());
            vtkPVRenderView::SetGeometryBounds(inInfo, this, bounds, matrix.GetPointer());
        }
    }
    return 1;
}
