#include "apps/mpi_session.h"

#include <chrono>
#include <cstring>
#include <string>
#include <thread>

#include <mpi.h>

#include "core/util/error.h"

namespace prism::app {
namespace {

constexpr int kTag = 20;  // one tag: every exchange is ordered per pair of ranks

// Fixed header, then text, rays, shadow rays, image and radiance back to back.
struct Header {
    int32_t kind;
    int32_t worker;
    int32_t item;
    double ms;
    uint32_t text_bytes, depths, image_words, radiance_floats;
};

template <typename T>
void append(std::vector<char>& bytes, const T* data, size_t count) {
    const char* from = reinterpret_cast<const char*>(data);
    bytes.insert(bytes.end(), from, from + count * sizeof(T));
}

template <typename T>
void take(const std::vector<char>& bytes, size_t& at, std::vector<T>& out, size_t count) {
    if (at + count * sizeof(T) > bytes.size()) throw Error("MPI: a work message is shorter than its header says");
    out.resize(count);
    if (count == 0) return;  // memcpy takes no null pointer, even for zero bytes
    std::memcpy(out.data(), bytes.data() + at, count * sizeof(T));
    at += count * sizeof(T);
}

std::vector<char> serialise(const WorkMessage& m) {
    Header h{int32_t(m.kind),
             m.worker,
             m.item,
             m.ms,
             uint32_t(m.text.size()),
             uint32_t(m.rays_per_depth.size()),
             uint32_t(m.image.size()),
             uint32_t(m.radiance.size())};
    std::vector<char> bytes;
    append(bytes, &h, 1);
    append(bytes, m.text.data(), m.text.size());
    append(bytes, m.rays_per_depth.data(), m.rays_per_depth.size());
    append(bytes, m.shadow_rays_per_depth.data(), m.shadow_rays_per_depth.size());
    append(bytes, m.image.data(), m.image.size());
    append(bytes, m.radiance.data(), m.radiance.size());
    return bytes;
}

WorkMessage deserialise(const std::vector<char>& bytes) {
    if (bytes.size() < sizeof(Header)) throw Error("MPI: a work message is shorter than its header");
    Header h;
    std::memcpy(&h, bytes.data(), sizeof h);
    WorkMessage m;
    m.kind = MessageKind(h.kind);
    m.worker = h.worker;
    m.item = h.item;
    m.ms = h.ms;
    size_t at = sizeof h;
    std::vector<char> text;
    take(bytes, at, text, h.text_bytes);
    m.text.assign(text.begin(), text.end());
    take(bytes, at, m.rays_per_depth, h.depths);
    take(bytes, at, m.shadow_rays_per_depth, h.depths);
    take(bytes, at, m.image, h.image_words);
    take(bytes, at, m.radiance, h.radiance_floats);
    return m;
}

void send(int to, const WorkMessage& message) {
    std::vector<char> bytes = serialise(message);
    MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, to, kTag, MPI_COMM_WORLD);
}

WorkMessage receive(int from, int& source) {
    MPI_Status status;
    MPI_Probe(from, kTag, MPI_COMM_WORLD, &status);
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::vector<char> bytes(static_cast<size_t>(count));
    MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    source = status.MPI_SOURCE;
    return deserialise(bytes);
}

}  // namespace

MpiSession::MpiSession() {
    // Serialized: a rank's device threads each exchange messages, one at a time (exchange_).
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        throw Error("MPI: the library does not support calls from several threads (MPI_THREAD_SERIALIZED)");
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm host;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &host);
    MPI_Comm_rank(host, &local_rank_);
    MPI_Comm_free(&host);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

WorkMessage MpiSession::exchange_with_coordinator(const WorkMessage& message) {
    std::lock_guard lock(exchange_);
    send(0, message);
    int source = 0;
    return receive(0, source);
}

void MpiSession::send_to_coordinator(const WorkMessage& message) {
    std::lock_guard lock(exchange_);
    send(0, message);
}

WorkMessage MpiSession::receive_from_workers(int& source_rank) {
    // A blocking probe spins a core for the whole frame (OpenMPI busy-waits), the core rank 0's own workers render
    // on; polling with short sleeps leaves it to them at a cost of well under a tile's time per message.
    for (int pending = 0;;) {
        MPI_Iprobe(MPI_ANY_SOURCE, kTag, MPI_COMM_WORLD, &pending, MPI_STATUS_IGNORE);
        if (pending) return receive(MPI_ANY_SOURCE, source_rank);
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

void MpiSession::send_to_worker(int rank, const WorkMessage& message) { send(rank, message); }

}  // namespace prism::app
