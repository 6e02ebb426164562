#include "vtkQuadcastGlyphRepresentation.h"

#include "vtkActor.h"
#include "vtkDataObject.h"
#include "vtkInformationVector.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPolyData.h"
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

void vtkQuadcastGlyphRepresentation::SetBondRadius(double r) { this->GetGlyphMapper()->SetBondRadius(r); }

int vtkQuadcastGlyphRepresentation::RequestData(vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector) {
    const int result = this->Superclass::RequestData(request, inputVector, outputVector);
    auto* input = vtkPolyData::SafeDownCast(vtkDataObject::GetData(inputVector[0], 0));
    auto* blocks = vtkMultiBlockDataSet::SafeDownCast(this->ProcessedData);
    if (input && input->GetNumberOfLines() > 0 && blocks && blocks->GetNumberOfBlocks() == 1) {
        auto* points = vtkPolyData::SafeDownCast(blocks->GetBlock(0));
        if (points && points->GetNumberOfPoints() == input->GetNumberOfPoints()) points->SetLines(input->GetLines());
    }
    return result;
}

void vtkQuadcastGlyphRepresentation::PrintSelf(ostream& os, vtkIndent indent) { this->Superclass::PrintSelf(os, indent); }

