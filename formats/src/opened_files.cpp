#include "opened_files.hpp"

#include <algorithm>
#include <memory>

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>

namespace sg::detail {
namespace {

class RecordingIoSystem : public Assimp::DefaultIOSystem {
public:
    Assimp::IOStream* Open(const char* file, const char* mode) override
    {
        Assimp::IOStream* stream = Assimp::DefaultIOSystem::Open(file, mode);
        // Importers open their main file more than once (format probing, then reading).
        if (stream != nullptr && std::find(opened.begin(), opened.end(), file) == opened.end())
            opened.emplace_back(file);
        return stream;
    }

    std::vector<std::string> opened;
};

}  // namespace

const std::vector<std::string>& record_opened_files(Assimp::Importer& importer)
{
    auto io = std::make_unique<RecordingIoSystem>();
    const std::vector<std::string>& opened = io->opened;
    importer.SetIOHandler(io.release());  // the importer owns it from here
    return opened;
}

}  // namespace sg::detail
