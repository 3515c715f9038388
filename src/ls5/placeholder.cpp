// Replaced by the LS5 codec sources.
namespace rangekit::ls5 {}
