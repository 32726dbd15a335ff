import './styles.css';
import { App } from './app.ts';

const app = new App();
void app.start();
