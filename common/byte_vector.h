// A growable byte buffer for the hot path of recording: appending n bytes is a capacity check,
// a memcpy of a size the compiler usually knows, and a size update, all inline. The shim
// appends a few bytes per argument of every GL call; std::vector<uint8_t>'s insert and resize go
// through out-of-line calls (_M_range_insert, _M_default_append) and a memmove or zero fill
// whatever the size: 20% of a glVertex3f's time in the shim (bench/call_cost.c under perf).
// Grown bytes are uninitialised: whoever grows them writes them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <utility>

namespace glcast {

class ByteVector {
public:
    ByteVector() = default;
    ByteVector(const ByteVector& o) { assign(o.begin(), o.end()); }
    ByteVector(ByteVector&& o) noexcept { swap(o); }
    ByteVector& operator=(const ByteVector& o) {
        if (this != &o) assign(o.begin(), o.end());
        return *this;
    }
    ByteVector& operator=(ByteVector&& o) noexcept {
        ByteVector(std::move(o)).swap(*this);
        return *this;
    }
    ~ByteVector() { std::free(data_); }

    uint8_t* data() { return data_; }
    const uint8_t* data() const { return data_; }
    size_t size() const { return size_; }
    size_t capacity() const { return capacity_; }
    bool empty() const { return size_ == 0; }
    uint8_t* begin() { return data_; }
    uint8_t* end() { return data_ + size_; }
    const uint8_t* begin() const { return data_; }
    const uint8_t* end() const { return data_ + size_; }
    uint8_t& operator[](size_t i) { return data_[i]; }
    uint8_t operator[](size_t i) const { return data_[i]; }

    void clear() { size_ = 0; }
    void reserve(size_t n) {
        if (n > capacity_) reallocate(n);
    }
    // n bytes more at the end, uninitialised; returns where they start.
    uint8_t* grow(size_t n) {
        if (capacity_ - size_ < n) reallocate(size_ + n > 2 * capacity_ ? size_ + n : 2 * capacity_);
        uint8_t* at = data_ + size_;
        size_ += n;
        return at;
    }
    void append(const void* p, size_t n) {
        if (n) std::memcpy(grow(n), p, n);
    }
    void resize(size_t n) {  // new bytes uninitialised
        if (n > size_) grow(n - size_);
        else size_ = n;
    }
    void assign(const uint8_t* first, const uint8_t* last) {
        clear();
        append(first, size_t(last - first));
    }
    void swap(ByteVector& o) noexcept {
        std::swap(data_, o.data_);
        std::swap(size_, o.size_);
        std::swap(capacity_, o.capacity_);
    }

private:
    void reallocate(size_t capacity) {
        void* p = std::realloc(data_, capacity);
        if (!p) throw std::bad_alloc();
        data_ = static_cast<uint8_t*>(p);
        capacity_ = capacity;
    }

    uint8_t* data_ = nullptr;
    size_t size_ = 0, capacity_ = 0;
};

}  // namespace glcast
