// memory.mesh, memory.views, memory.volume: nodes whose output is data the host holds (a mesh a
// TD built in numpy, views already loaded), so that such data enters a pipeline as any node's
// output does and the pipeline runs through the one executor. The data is kept under a key the
// node's `key` parameter names.
#include <map>
#include <mutex>

#include "core/error.h"
#include "core/stage.h"
#include "module.h"

namespace cm::py {

namespace {

std::mutex store_mutex;
std::map<std::string, Data>& store() {
    static auto* s = new std::map<std::string, Data>(); // outlives the interpreter's teardown
    return *s;
}

class MemoryStage : public Stage {
public:
    explicit MemoryStage(DataKind kind) : kind_(kind) {}
    Data run(const Inputs&, Context&) override {
        std::lock_guard<std::mutex> lock(store_mutex);
        auto it = store().find(key_);
        if (it == store().end()) throw Error("no data is held under key \"" + key_ + "\" (it was released)");
        if (kind_of(it->second) != kind_)
            throw Error("the data under key \"" + key_ + "\" is " + to_string(kind_of(it->second)) + ", not " +
                        to_string(kind_));
        return it->second;
    }

protected:
    StageSignature signature() const override {
        const std::string kind = to_string(kind_);
        return {"memory." + kind, "The " + kind + " the host program (the Python module) handed in", {}, kind_};
    }
    void declare(ParamBinder& b) override {
        b.add(key_, ParamSpec::String("key", std::nullopt, "the host's key of the data (conceptmesh.memory_put)"));
    }

private:
    DataKind kind_;
    std::string key_;
};

} // namespace

std::string memory_put(Data d) {
    static std::atomic<unsigned long> next{0};
    std::lock_guard<std::mutex> lock(store_mutex);
    std::string key = std::string(to_string(kind_of(d))) + "-" + std::to_string(++next);
    store()[key] = std::move(d);
    return key;
}

void memory_drop(const std::string& key) {
    std::lock_guard<std::mutex> lock(store_mutex);
    store().erase(key);
}

void add_memory_stages(Registry& r) {
    for (DataKind kind : {DataKind::Mesh, DataKind::Views, DataKind::Volume}) {
        StageEntry e;
        e.name = std::string("memory.") + to_string(kind);
        e.plugin = "python";
        e.plugin_version = CONCEPTMESH_VERSION_STRING;
        e.create = [kind] { return std::make_unique<MemoryStage>(kind); };
        r.add(std::move(e));
    }
}

} // namespace cm::py
