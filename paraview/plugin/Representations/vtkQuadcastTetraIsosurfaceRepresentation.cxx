#include "vtkQuadcastTetraIsosurfaceRepresentation.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkQuadcastTetraIsosurfaceMapper.h"
#include "vtkUnstructuredGrid.h"

vtkStandardNewMacro(vtkQuadcastTetraIsosurfaceRepresentation);

vtkQuadcastTetraIsosurfaceRepresentation::vtkQuadcastTetraIsosurfaceRepresentation() { this->SetMapper(this->Mapper); }

vtkQuadcastTetraIsosurfaceRepresentation::~vtkQuadcastTetraIsosurfaceRepresentation() = default;

void vtkQuadcastTetraIsosurfaceRepresentation::SetIsovalue(double value) { this->Mapper->SetIsovalue(value); }

void vtkQuadcastTetraIsosurfaceRepresentation::SelectScalarArray(int, int, int, int, const char* name) {
    this->Mapper->SetScalarArray(name && name[0] ? name : nullptr);
}

int vtkQuadcastTetraIsosurfaceRepresentation::FillInputPortInformation(int, vtkInformation* info) {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
}

int vtkQuadcastTetraIsosurfaceRepresentation::RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                                                          vtkInformationVector* outputVector) {
    vtkMath::UninitializeBounds(this->DataBounds);
    auto cache = vtkSmartPointer<vtkUnstructuredGrid>::New();
    this->Cache = cache;
    if (inputVector[0]->GetNumberOfInformationObjects() == 1) {
        if (vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0)) {
            cache->ShallowCopy(input);
            if (cache->GetNumberOfPoints() > 0) cache->GetBounds(this->DataBounds);
        }
    }
    return this->Superclass::RequestData(request, inputVector, outputVector);
}

void vtkQuadcastTetraIsosurfaceRepresentation::PrintSelf(ostream& os, vtkIndent indent) { this->Superclass::PrintSelf(os, indent); }
