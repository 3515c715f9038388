// The overview's work per animation frame, so that a hundred cards never make one long task:
// the values that came since the last frame are written once, and the sparklines are redrawn
// every DRAW_MS a few at a time within BUDGET_MS a frame, and only for cards on screen.
import type { Card } from './card';

const DRAW_MS = 500;
const BUDGET_MS = 4;

export class OverviewFrames {
  private readonly cards = new Map<Element, Card>();
  private readonly onScreen = new Set<Card>();
  private readonly unwritten = new Set<Card>();
  private readonly queue: Card[] = [];  // sparklines to redraw, in turn
  private readonly queued = new Set<Card>();
  private requested = false;
  private readonly observer: IntersectionObserver;

  // `now`: the service's clock in seconds, where each sparkline's window ends.
  constructor(private readonly now: () => number) {
    // A card coming into view (scrolled to, or shown by the filter) is drawn at once.
    this.observer = new IntersectionObserver((entries) => {
      for (const entry of entries) {
        const card = this.cards.get(entry.target);
        if (!card) continue;
        if (entry.isIntersecting) {
          this.onScreen.add(card);
          this.enqueue(card);
        } else {
          this.onScreen.delete(card);
        }
      }
    }, { rootMargin: '100px' });
    setInterval(() => {
      if (document.hidden) return;
      for (const card of this.onScreen) this.enqueue(card);
    }, DRAW_MS);
  }

  watch(card: Card): void {
    this.cards.set(card.root, card);
    this.observer.observe(card.root);
  }

  // The card has a value to write; a hidden card's waits until it is shown.
  changed(card: Card): void {
    this.unwritten.add(card);
    this.request();
  }

  private enqueue(card: Card): void {
    if (this.queued.has(card)) return;
    this.queued.add(card);
    this.queue.push(card);
    this.request();
  }

  private request(): void {
    if (this.requested) return;
    this.requested = true;
    requestAnimationFrame(() => this.frame());
  }

  private frame(): void {
    this.requested = false;
    const started = performance.now();
    const time = this.now();
    // Draws first: they read the layout, which the writes below make stale.
    while (this.queue.length > 0 && performance.now() - started < BUDGET_MS) {
      const card = this.queue.shift() as Card;
      this.queued.delete(card);
      if (this.onScreen.has(card)) card.draw(time);
    }
    for (const card of this.unwritten) {
      if (card.root.hidden) continue;
      card.flush();
      this.unwritten.delete(card);
    }
    if (this.queue.length > 0) this.request();
  }
}
