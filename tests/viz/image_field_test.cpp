// write_image_field read back with VTK's own XML image data reader: placement (dimensions,
// origin, spacing), every array value bit for bit (infinities and NaN included), triangle ids
// as Int64 with -1 for none, field data, the encoding shared with the export; and refusals
// that leave no file.

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/viz/image_field.hpp"
#include "support/scratch_dir.hpp"
#include "support/vtk_readback.hpp"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using viz::ImageField;

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float nan = std::numeric_limits<float>::quiet_NaN();

vtkSmartPointer<vtkImageData> read_vti(const fs::path& path)
{
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    if (image == nullptr || image->GetNumberOfPoints() == 0)
        throw std::runtime_error(path.string() + ": VTK read nothing");
    return image;
}

/// A 3 x 2 x 4 field: a float array with infinities and NaN, a 3-component array, ids.
struct Sample {
    std::vector<float> values;
    std::vector<float> vectors;
    std::vector<std::uint32_t> ids;
    ImageField field;

    Sample()
    {
        field.geometry = {{3, 2, 4}, {-1.5, 0.25, 1e3}, {0.5, 2.0, 1e-3}};
        const std::size_t n = 24;
        for (std::size_t i = 0; i < n; ++i) {
            values.push_back(static_cast<float>(i) * 0.25f - 2.0f);
            for (int c = 0; c < 3; ++c) vectors.push_back(static_cast<float>(10 * i + c));
            ids.push_back(i % 5 == 0 ? 0xFFFFFFFFu : static_cast<std::uint32_t>(1000 + i));
        }
        values[3] = inf;
        values[4] = nan;
        values[5] = -0.0f;
        ids[7] = 0xFFFFFFFEu;  // the largest real id
        field.floats = {{"signed_distance", values, 1}, {"closest_point", vectors, 3}};
        field.ids = {{"triangle_id", ids}};
        field.text_facts = {{"query", "signed-distance"}, {"source_name", "bunny.obj"}};
        field.number_facts = {{"padding", 0.05}, {"nsamples", 3}};
    }
};

TEST(ImageField, ReadsBackWithVtkPlacedAndBitForBit)
{
    ScratchDir scratch;
    const fs::path path = scratch / "field.vti";
    Sample s;
    {
        OutputFile output(path);
        viz::write_image_field(output, s.field);
    }
    const vtkSmartPointer<vtkImageData> image = read_vti(path);
    int dims[3];
    image->GetDimensions(dims);
    EXPECT_EQ(dims[0], 3);
    EXPECT_EQ(dims[1], 2);
    EXPECT_EQ(dims[2], 4);
    double origin[3], spacing[3];
    image->GetOrigin(origin);
    image->GetSpacing(spacing);
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(origin[a], s.field.geometry.origin[a]) << a;
        EXPECT_EQ(spacing[a], s.field.geometry.spacing[a]) << a;
    }
    // Point n lies at origin + (i, j, k) spacing with n = i + 3 (j + 2 k): x fastest.
    double p[3];
    image->GetPoint(1 + 3 * (1 + 2 * 2), p);
    EXPECT_EQ(p[0], -1.5 + 0.5);
    EXPECT_EQ(p[1], 0.25 + 2.0);
    EXPECT_EQ(p[2], 1e3 + 2 * 1e-3);

    vtkPointData* data = image->GetPointData();
    ASSERT_NE(data->GetScalars(), nullptr);
    EXPECT_STREQ(data->GetScalars()->GetName(), "signed_distance") << "the active scalars";
    vtkDataArray* values = data->GetArray("signed_distance");
    vtkDataArray* vectors = data->GetArray("closest_point");
    vtkDataArray* ids = data->GetArray("triangle_id");
    ASSERT_NE(values, nullptr);
    ASSERT_NE(vectors, nullptr);
    ASSERT_NE(ids, nullptr);
    EXPECT_EQ(values->GetDataType(), VTK_FLOAT);
    EXPECT_EQ(vectors->GetNumberOfComponents(), 3);
    EXPECT_EQ(ids->GetDataTypeSize(), 8);
    for (vtkIdType i = 0; i < 24; ++i) {
        const auto n = static_cast<std::size_t>(i);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(static_cast<float>(values->GetComponent(i, 0))),
                  std::bit_cast<std::uint32_t>(s.values[n]))
            << i;
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(vectors->GetComponent(i, c), s.vectors[3 * n + static_cast<std::size_t>(c)]);
        const double expected_id = s.ids[n] == 0xFFFFFFFFu ? -1.0 : static_cast<double>(s.ids[n]);
        EXPECT_EQ(ids->GetComponent(i, 0), expected_id) << i;
    }

    EXPECT_EQ(field_string(image, "query"), "signed-distance");
    EXPECT_EQ(field_string(image, "source_name"), "bunny.obj");
    EXPECT_EQ(field_number(image, "padding"), 0.05);
    EXPECT_EQ(field_number(image, "nsamples"), 3.0);

    const std::string head = file_head(path);
    EXPECT_NE(head.find("<VTKFile type=\"ImageData\""), std::string::npos) << head;
    EXPECT_NE(head.find("header_type=\"UInt64\""), std::string::npos);
    EXPECT_NE(head.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
    EXPECT_NE(head.find("format=\"appended\""), std::string::npos);
}

TEST(ImageField, RefusalsNameTheTargetAndLeaveNoFile)
{
    ScratchDir scratch;
    const fs::path path = scratch / "field.vti";
    const auto refusal = [&](const ImageField& field) {
        std::string message;
        try {
            OutputFile output(path);
            viz::write_image_field(output, field);
        } catch (const ConfigError& e) {
            message = e.what();
        }
        EXPECT_FALSE(fs::exists(path));
        EXPECT_TRUE(fs::is_empty(scratch.path())) << "a temporary file was left";
        return message;
    };
    Sample s;
    ImageField short_array = s.field;
    short_array.floats[0].values = std::span<const float>(s.values).first(23);
    EXPECT_EQ(refusal(short_array),
              path.string() + ": array signed_distance holds 23 values for 24 points of 1 "
                              "component(s)");
    ImageField short_ids = s.field;
    short_ids.ids[0].values = std::span<const std::uint32_t>(s.ids).first(2);
    EXPECT_EQ(refusal(short_ids), path.string() + ": array triangle_id holds 2 values for 24 "
                                                  "points");
    ImageField flat = s.field;
    flat.geometry.spacing[1] = 0.0;
    EXPECT_NE(refusal(flat).find("spacing is not positive"), std::string::npos);
    ImageField far = s.field;
    far.geometry.origin[2] = std::numeric_limits<double>::infinity();
    EXPECT_NE(refusal(far).find("on axis 2 is not finite"), std::string::npos);
    ImageField none = s.field;
    none.floats.clear();
    EXPECT_NE(refusal(none).find("at least one float array"), std::string::npos);
}

}  // namespace
}  // namespace sg::test
